// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "base/config/check.hpp"
#include "hal/modbus/word_order.hpp"

namespace excite::hal::modbus {

// Protocol limits (Modbus application protocol v1.1b3 §6.12, §6.3/6.4).
inline constexpr std::uint32_t address_space = 65536;      // registers 0..65535
inline constexpr std::uint32_t max_write_registers = 123;  // FC16 per request
inline constexpr std::uint32_t max_read_registers = 125;   // FC03/FC04 per request

// One value in the register map, as written in the gateway configuration.
//   type "float32": engineering units as IEEE 754 in two registers, word_order applies.
//   type "int16"/"uint16": one register, scaled linearly between the engineering range
//     [eng_min, eng_max] and the raw range [raw_min, raw_max] (default: the type's full
//     range, e.g. 0..65535). Setpoints outside the engineering range are clamped to it
//     (and counted); values read outside the raw range are converted without clamping,
//     so a transmitter fault stays visible.
struct RegisterEntry {
  std::string name;                 // for messages and the run log
  std::uint32_t address = 0;        // protocol (PDU) address, 0-based
  int function_code = 16;           // setpoints: 16; values: 3 (holding) or 4 (input)
  std::string type = "float32";     // float32, int16, uint16
  std::string word_order = "ABCD";  // float32: ABCD, CDAB, BADC or DCBA
  double eng_min = 0.0;             // int16/uint16: engineering range (units of the value)
  double eng_max = 0.0;
  std::optional<std::int32_t> raw_min;  // int16/uint16: raw range; default: type's full range
  std::optional<std::int32_t> raw_max;
};

struct RegisterMap {
  std::vector<RegisterEntry> setpoints;             // written with FC16, in this order
  std::vector<RegisterEntry> values;                // read with FC03/FC04, in this order
  std::optional<std::uint32_t> heartbeat_address;   // uint16 counter written with FC16
  std::uint32_t write_chunk = max_write_registers;  // registers per FC16 request, 2..123
  std::uint32_t read_chunk = max_read_registers;    // registers per FC03/04 request, 2..125
};

// ---- The compiled plan: what the cyclic path executes, sized at configuration. ----

enum class RegisterType : std::uint8_t { float32, int16, uint16 };

// How one value is converted between engineering units and its registers.
struct Codec {
  RegisterType type = RegisterType::float32;
  WordOrder order = WordOrder::abcd;
  double eng_min = 0.0;
  double eng_max = 0.0;
  double raw_min = 0.0;
  double raw_max = 0.0;
  std::size_t offset = 0;     // index of the first register in the write/read image
  std::uint16_t address = 0;  // its first register (values: where write_value writes)
  int function_code = 16;     // how it is transferred: 16, or 3/4 for a value
};

// One Modbus request: `count` registers from `address`, held in the image at `offset`.
struct Request {
  int function_code = 16;
  std::uint16_t address = 0;
  std::uint16_t count = 0;
  std::size_t offset = 0;
};

struct RegisterPlan {
  std::vector<Codec> setpoints;  // same order as RegisterMap::setpoints
  std::optional<std::size_t> heartbeat_offset;
  std::vector<Request> writes;  // FC16, contiguous runs split at write_chunk
  std::size_t write_image_size = 0;
  std::vector<Codec> values;   // same order as RegisterMap::values
  std::vector<Request> reads;  // FC03/FC04, contiguous runs split at read_chunk
  std::size_t read_image_size = 0;
};

// Checks the map against the protocol (addresses, overlaps, chunk limits, types, word
// orders, ranges) and compiles it into `plan`. Requests cover contiguous registers only
// (a gap is never written or read) and never split a value across two requests.
// On failure the config::Check names the first offending field; `plan` is left empty.
config::Check compile_register_map(const RegisterMap& map, RegisterPlan& plan);

// Linear scaling of one int16/uint16 value (codec.type != float32).
// to_raw clamps to the engineering range and reports whether it did.
std::uint16_t to_raw(const Codec& codec, double engineering, bool& clamped) noexcept;
double from_raw(const Codec& codec, std::uint16_t raw) noexcept;

// Registers a type occupies (float32: 2, int16/uint16: 1).
std::uint32_t register_count(RegisterType type) noexcept;

}  // namespace excite::hal::modbus
