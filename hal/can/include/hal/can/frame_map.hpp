// SPDX-License-Identifier: MIT
#pragma once

#include <linux/can.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/config/check.hpp"
#include "excite/hal/status.hpp"

namespace excite::hal::can {

// One value carried in a classic CAN frame (8 data bytes), as written in the gateway
// configuration. engineering = raw * scale + offset; on write raw = (engineering -
// offset) / scale, rounded to the nearest integer and clamped to the type's range
// (clamps are counted). float32 carries (engineering - offset) / scale as IEEE 754.
struct CanSignal {
  std::string name;                   // for messages and the run log
  std::uint32_t id = 0;               // identifier: 0..0x7FF, or 0..0x1FFFFFFF if extended
  bool extended = false;              // 29-bit identifier
  std::uint32_t byte_offset = 0;      // first payload byte, 0..7
  std::string type = "int16";         // int8, uint8, int16, uint16, int32, uint32, float32
  std::string byte_order = "little";  // "little" (Intel) or "big" (Motorola)
  double scale = 1.0;                 // engineering units per raw count, != 0
  double offset = 0.0;                // engineering units at raw 0
};

struct CanFrameMap {
  std::vector<CanSignal> setpoints;    // sent every write(), grouped into frames by identifier
  std::vector<CanSignal> values;       // taken from received frames by identifier
  std::optional<CanSignal> heartbeat;  // uint8 or uint16 counter in a setpoint frame (scale unused)
};

// ---- compiled form, sized at configuration ----

enum class SignalType : std::uint8_t { int8, uint8, int16, uint16, int32, uint32, float32 };

/// The raw values an integer signal type holds, [low, high]; false for float32 (its range
/// is not a limit a setpoint meets).
bool raw_range(SignalType type, double& low, double& high) noexcept;

struct SignalCodec {
  std::size_t frame = 0;  // index into CanPlan::tx or CanPlan::rx
  std::uint8_t offset = 0;
  std::uint8_t size = 0;  // bytes
  SignalType type = SignalType::int16;
  bool big_endian = false;
  double scale = 1.0;
  double offset_eng = 0.0;
};

struct RxFrame {
  canid_t id = 0;        // with CAN_EFF_FLAG for extended identifiers
  std::uint8_t dlc = 0;  // bytes the mapped signals need
};

struct CanPlan {
  std::vector<can_frame> tx;           // one template per setpoint identifier (id, dlc set)
  std::vector<SignalCodec> setpoints;  // same order as CanFrameMap::setpoints
  std::optional<SignalCodec> heartbeat;
  std::vector<RxFrame> rx;          // one per value identifier
  std::vector<SignalCodec> values;  // same order as CanFrameMap::values
};

// Checks identifiers, byte layout (fits in 8 bytes, no two signals share a byte), types,
// byte orders and scaling, and compiles the map. An identifier is either sent or
// received, never both. On failure `plan` is left empty.
config::Check compile_frame_map(const CanFrameMap& map, CanPlan& plan);

// Fills `frames` (size plan.tx.size()) with the setpoints (engineering units) and the
// heartbeat. Returns bad_argument (frames unspecified) for a wrong size or a non-finite
// setpoint; adds the number of clamped setpoints to `clamped`.
StatusCode pack_setpoints(const CanPlan& plan, std::span<const double> setpoints,
                          std::uint16_t heartbeat, std::span<can_frame> frames,
                          std::uint64_t& clamped) noexcept;

// Index into plan.rx of a received frame's identifier, if it is mapped.
std::optional<std::size_t> find_rx(const CanPlan& plan, const can_frame& frame) noexcept;

// Decodes the values carried by a received mapped frame into `values` (size
// plan.values.size()); false (values untouched) if the frame is shorter than the map needs.
bool unpack_values(const CanPlan& plan, std::size_t rx_index, const can_frame& frame,
                   std::span<double> values) noexcept;

}  // namespace excite::hal::can
