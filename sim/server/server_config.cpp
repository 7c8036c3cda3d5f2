// SPDX-License-Identifier: MIT
#include "sim/server/server_config.hpp"

#include <limits>
#include <string>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "hal/modbus/register_entry_toml.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::sim::server {
namespace {

using config::Table;

PlantSettings read_plant(const Table& t) {
  t.only_keys({"library", "file", "sample_time_min", "input_baseline", "output_baseline",
               "noise_variance", "noise_seed", "watchdog_s", "input_min", "input_max",
               "tau_high_min", "beta", "controller", "offset_limit"});
  PlantSettings plant;
  plant.library = t.text("library").value_or("");
  plant.file = t.text("file").value_or("");
  if (!plant.library.empty() && !plant.file.empty()) {
    t.fail("file", "\"" + plant.file + "\"", "either library or file, not both");
  }
  plant.sample_time_min = t.positive("sample_time_min", "minutes").value_or(1.0);
  plant.input_baseline = t.numbers("input_baseline");
  plant.output_baseline = t.numbers("output_baseline");
  plant.noise_variance = t.numbers("noise_variance", true);
  for (std::size_t i = 0; i < plant.noise_variance.size(); ++i) {
    if (plant.noise_variance[i] < 0.0) {
      t.fail("noise_variance[" + std::to_string(i) + "]",
             config::format_number(plant.noise_variance[i]), "a variance >= 0");
    }
  }
  if (const auto seed =
          t.integer("noise_seed", 0, std::numeric_limits<std::int64_t>::max(), "a seed >= 0")) {
    plant.noise_seed = static_cast<std::uint64_t>(*seed);
  }
  plant.tau_high_min = t.non_negative("tau_high_min", "minutes (0: not known)").value_or(0.0);
  plant.beta = t.non_negative("beta", "settling time in units of tau_high_min").value_or(0.0);
  plant.watchdog_s = t.non_negative("watchdog_s", "wall-clock seconds (0: off)").value_or(0.0);
  plant.controller = t.text("controller").value_or("");
  plant.offset_limit = t.numbers("offset_limit");
  for (std::size_t k = 0; k < plant.offset_limit.size(); ++k) {
    if (!(plant.offset_limit[k] > 0.0)) {
      t.fail("offset_limit[" + std::to_string(k) + "]",
             config::format_number(plant.offset_limit[k]),
             "a bound > 0 on the size of that test offset");
    }
  }
  plant.input_min = t.numbers("input_min");
  plant.input_max = t.numbers("input_max");
  if (plant.input_min.size() != plant.input_max.size()) {
    t.fail("input_max", "(" + std::to_string(plant.input_max.size()) + " values)",
           "as many values as input_min (" + std::to_string(plant.input_min.size()) + ")");
  }
  for (std::size_t i = 0; i < plant.input_min.size(); ++i) {
    if (!(plant.input_min[i] < plant.input_max[i])) {
      t.fail("input_max[" + std::to_string(i) + "]", config::format_number(plant.input_max[i]),
             "a limit above input_min[" + std::to_string(i) +
                 "] = " + config::format_number(plant.input_min[i]));
    }
  }
  return plant;
}

// One [[registers.setpoints]] / [[registers.values]] entry: a name and hal's schema.
std::vector<hal::modbus::RegisterEntry> read_entries(const Table& registers, const char* key,
                                                     hal::modbus::EntryKind kind) {
  std::vector<std::string> known(hal::modbus::register_entry_keys.begin(),
                                 hal::modbus::register_entry_keys.end());
  known.insert(known.begin(), "name");
  std::vector<hal::modbus::RegisterEntry> out;
  for (const Table& t : registers.tables(key)) {
    t.only_keys(known);
    hal::modbus::RegisterEntry e = hal::modbus::read_register_entry(t, kind);
    e.name = t.text("name").value_or("");
    out.push_back(std::move(e));
  }
  return out;
}

ServerRegisters read_registers(const Table& t) {
  t.only_keys({"setpoints", "values", "heartbeat_address", "heartbeat_echo_address",
               "heartbeat_echo_function_code", "control_address", "command_address", "write_chunk",
               "read_chunk", "offset_address", "controller_address", "controller_switch_address"});
  ServerRegisters regs;
  regs.map.setpoints = read_entries(t, "setpoints", hal::modbus::EntryKind::setpoint);
  regs.map.values = read_entries(t, "values", hal::modbus::EntryKind::value);
  hal::modbus::read_map_settings(t, regs.map);
  if (!regs.map.heartbeat_address) {
    t.fail_missing("heartbeat_address", "a holding register address 0..65535");
  }
  regs.heartbeat_echo_address = static_cast<std::uint32_t>(
      t.required_integer("heartbeat_echo_address", 0, 65535, "a register address 0..65535"));
  regs.heartbeat_echo_function_code = static_cast<int>(
      t.integer("heartbeat_echo_function_code", 3, 4, "3 (holding) or 4 (input register)")
          .value_or(3));
  if (const auto c = t.integer(
          "control_address", 0, 65536 - control_block_size,
          "a holding address with room for " + std::to_string(control_block_size) + " registers")) {
    regs.control_address = static_cast<std::uint32_t>(*c);
  }
  if (const auto c =
          t.integer("command_address", 0, 65535, "a holding register address 0..65535")) {
    regs.command_address = static_cast<std::uint32_t>(*c);
  }
  // Closed loop: the blocks' sizes depend on the plant, checked by compile_layout.
  const auto address = [&t](const char* key, const char* what) -> std::optional<std::uint32_t> {
    if (const auto a = t.integer(key, 0, 65535, what)) return static_cast<std::uint32_t>(*a);
    return std::nullopt;
  };
  regs.offset_address = address("offset_address", "a holding register address 0..65535");
  regs.controller_address = address("controller_address", "an input register address 0..65535");
  regs.controller_switch_address =
      address("controller_switch_address", "a holding register address 0..65535");
  return regs;
}

}  // namespace

ServerConfig parse_server_config(std::string_view toml_text, std::string_view source) {
  const toml::table doc = config::parse(toml_text, source);
  const Table root(doc, "", source);
  root.only_keys({"plant", "registers"});
  ServerConfig out;
  if (const auto plant = root.table("plant")) out.plant = read_plant(*plant);
  out.registers = read_registers(root.required_table("registers", "a [registers] table"));
  check_registers(out.registers, source);
  return out;
}

ServerConfig load_server_config(const std::filesystem::path& path) {
  ServerConfig out = parse_server_config(config::read_file(path), path.string());
  out.base_directory = path.parent_path();
  return out;
}

}  // namespace excite::sim::server
