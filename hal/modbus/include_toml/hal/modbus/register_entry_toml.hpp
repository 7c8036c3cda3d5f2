// SPDX-License-Identifier: MIT
#pragma once
// The register-map schema: how a configuration file writes one register-map entry and the
// map's own settings. One definition, read by both the gateway's configuration
// (firmware/app/gateway_config.cpp, [[setpoints]], [[values]], [map]) and the plant
// server's (sim/server/server_config.cpp, [[registers.setpoints]], [[registers.values]],
// [registers]), so the two sides of one link cannot default a field differently; and
// written by one writer beside the reader (format_register_entry, format_map_settings:
// the plant server's configuration writer and `excite loop-config`'s gateway side), so
// what is written is what the reader reads back.
//
// Entry keys and defaults (hal's RegisterEntry):
//   address        required, an integer 0..65535 (PDU address; the span is checked by
//                  validate()/compile_register_map)
//   function_code  setpoints 16; values 3 (holding registers; 4 = input registers)
//   type           "float32" (or "int16", "uint16")
//   word_order     "ABCD" (float32: ABCD, CDAB, BADC, DCBA)
//   eng_min, eng_max  0, 0 (int16/uint16 engineering range; finite numbers)
//   raw_min, raw_max  the type's full range (integers -32768..65535)
// Map keys: heartbeat_address (0..65535, optional here), write_chunk (2..123),
// read_chunk (2..125).
//
// Start-up code: reads through base/config and throws config::Error in its one form.
// Built apart from excite_hal_modbus (library excite_hal_modbus_toml) because it throws.

#include <array>
#include <string>
#include <string_view>

#include "base/config/table.hpp"
#include "hal/modbus/register_map.hpp"

namespace excite::hal::modbus {

/// Which list an entry belongs to; it decides the default function code.
enum class EntryKind : std::uint8_t { setpoint, value };

/// Default function code: 16 (write multiple registers) for setpoints, 3 (read holding
/// registers) for values.
constexpr int default_function_code(EntryKind kind) noexcept {
  return kind == EntryKind::setpoint ? 16 : 3;
}

/// The keys of an entry that belong to the register map (an entry may carry its owner's
/// keys too: name, limits, role, …).
inline constexpr std::array<std::string_view, 8> register_entry_keys = {
    "address", "function_code", "type", "word_order", "eng_min", "eng_max", "raw_min", "raw_max"};

/// Reads the register fields of one entry (name is left empty: its owner names it).
RegisterEntry read_register_entry(const config::Table& entry, EntryKind kind);

/// Reads heartbeat_address, write_chunk and read_chunk from `table` into `map` (the keys
/// that are absent keep map's values).
void read_map_settings(const config::Table& table, RegisterMap& map);

/// The register fields of `e` as TOML lines, one "key = value\n" each, that
/// read_register_entry reads back into the same fields: address; function_code for a
/// value (and for a setpoint whose code is not 16); type; float32: word_order; int16 and
/// uint16: eng_min, eng_max, and raw_min, raw_max when set. The name is its owner's to write.
std::string format_register_entry(const RegisterEntry& e, EntryKind kind);

/// heartbeat_address (when set), write_chunk and read_chunk as TOML lines that
/// read_map_settings reads back.
std::string format_map_settings(const RegisterMap& map);

}  // namespace excite::hal::modbus
