// SPDX-License-Identifier: MIT
#include "hal/modbus/register_entry_toml.hpp"

#include "base/config/writer.hpp"

namespace excite::hal::modbus {

RegisterEntry read_register_entry(const config::Table& entry, EntryKind kind) {
  RegisterEntry e;
  e.address = static_cast<std::uint32_t>(
      entry.required_integer("address", 0, address_space - 1, "a register address 0..65535"));
  e.function_code = static_cast<int>(
      entry.integer("function_code", 0, 255, "a Modbus function code (16; values 3 or 4)")
          .value_or(default_function_code(kind)));
  e.type = entry.text("type").value_or(e.type);
  e.word_order = entry.text("word_order").value_or(e.word_order);
  e.eng_min = entry.number("eng_min").value_or(e.eng_min);
  e.eng_max = entry.number("eng_max").value_or(e.eng_max);
  if (const auto v = entry.integer("raw_min", -32768, 65535)) {
    e.raw_min = static_cast<std::int32_t>(*v);
  }
  if (const auto v = entry.integer("raw_max", -32768, 65535)) {
    e.raw_max = static_cast<std::int32_t>(*v);
  }
  return e;
}

void read_map_settings(const config::Table& table, RegisterMap& map) {
  if (const auto v =
          table.integer("heartbeat_address", 0, address_space - 1, "a register address 0..65535")) {
    map.heartbeat_address = static_cast<std::uint32_t>(*v);
  }
  if (const auto v = table.integer("write_chunk", 2, max_write_registers)) {
    map.write_chunk = static_cast<std::uint32_t>(*v);
  }
  if (const auto v = table.integer("read_chunk", 2, max_read_registers)) {
    map.read_chunk = static_cast<std::uint32_t>(*v);
  }
}

std::string format_register_entry(const RegisterEntry& e, EntryKind kind) {
  using config::toml_number;
  using config::toml_string;
  std::string out = "address = " + std::to_string(e.address) + "\n";
  if (kind == EntryKind::value || e.function_code != default_function_code(kind)) {
    out += "function_code = " + std::to_string(e.function_code) + "\n";
  }
  out += "type = " + toml_string(e.type) + "\n";
  if (e.type == "float32") return out + "word_order = " + toml_string(e.word_order) + "\n";
  out += "eng_min = " + toml_number(e.eng_min) + "\neng_max = " + toml_number(e.eng_max) + "\n";
  if (e.raw_min) out += "raw_min = " + std::to_string(*e.raw_min) + "\n";
  if (e.raw_max) out += "raw_max = " + std::to_string(*e.raw_max) + "\n";
  return out;
}

std::string format_map_settings(const RegisterMap& map) {
  std::string out;
  if (map.heartbeat_address) {
    out += "heartbeat_address = " + std::to_string(*map.heartbeat_address) + "\n";
  }
  return out + "write_chunk = " + std::to_string(map.write_chunk) +
         "\nread_chunk = " + std::to_string(map.read_chunk) + "\n";
}

}  // namespace excite::hal::modbus
