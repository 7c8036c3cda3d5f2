// SPDX-License-Identifier: MIT
#include "sim/server/config_writer.hpp"

#include <sstream>

#include "hal/modbus/register_entry_toml.hpp"

namespace excite::sim::server {
namespace {

std::string numbers(const std::vector<double>& xs) {
  std::string out = "[";
  for (std::size_t i = 0; i < xs.size(); ++i) out += (i == 0 ? "" : ", ") + toml_number(xs[i]);
  return out + "]";
}

void entry(std::ostringstream& os, const char* table, const hal::modbus::RegisterEntry& e,
           hal::modbus::EntryKind kind) {
  os << "\n[[registers." << table << "]]\n";
  if (!e.name.empty()) os << "name = " << toml_string(e.name) << "\n";
  os << hal::modbus::format_register_entry(e, kind);
}

}  // namespace

std::string format_server_config(const ServerConfig& config, const std::string& header) {
  std::ostringstream os;
  if (!header.empty()) os << "# " << header << "\n";
  const PlantSettings& p = config.plant;
  os << "[plant]\n";
  if (!p.library.empty()) os << "library = " << toml_string(p.library) << "\n";
  if (!p.file.empty()) os << "file = " << toml_string(p.file) << "\n";
  os << "sample_time_min = " << toml_number(p.sample_time_min) << "\n";
  if (!p.input_baseline.empty()) os << "input_baseline = " << numbers(p.input_baseline) << "\n";
  if (!p.output_baseline.empty()) {
    os << "output_baseline = " << numbers(p.output_baseline) << "\n";
  }
  if (!p.noise_variance.empty()) os << "noise_variance = " << numbers(p.noise_variance) << "\n";
  os << "noise_seed = " << p.noise_seed << "\n";
  if (p.tau_high_min > 0.0) os << "tau_high_min = " << toml_number(p.tau_high_min) << "\n";
  if (p.beta > 0.0) os << "beta = " << toml_number(p.beta) << "\n";
  if (p.watchdog_s > 0.0) os << "watchdog_s = " << toml_number(p.watchdog_s) << "\n";
  if (!p.input_min.empty()) {
    os << "input_min = " << numbers(p.input_min) << "\ninput_max = " << numbers(p.input_max)
       << "\n";
  }
  if (!p.controller.empty()) os << "controller = " << toml_string(p.controller) << "\n";
  if (!p.offset_limit.empty()) os << "offset_limit = " << numbers(p.offset_limit) << "\n";

  const ServerRegisters& r = config.registers;
  os << "\n[registers]\n";
  os << hal::modbus::format_map_settings(r.map);
  os << "heartbeat_echo_address = " << r.heartbeat_echo_address << "\n";
  os << "heartbeat_echo_function_code = " << r.heartbeat_echo_function_code << "\n";
  if (r.command_address) os << "command_address = " << *r.command_address << "\n";
  if (r.control_address) os << "control_address = " << *r.control_address << "\n";
  if (r.offset_address) os << "offset_address = " << *r.offset_address << "\n";
  if (r.controller_address) os << "controller_address = " << *r.controller_address << "\n";
  if (r.controller_switch_address) {
    os << "controller_switch_address = " << *r.controller_switch_address << "\n";
  }
  for (const auto& e : r.map.setpoints) entry(os, "setpoints", e, hal::modbus::EntryKind::setpoint);
  for (const auto& e : r.map.values) entry(os, "values", e, hal::modbus::EntryKind::value);
  return os.str();
}

}  // namespace excite::sim::server
