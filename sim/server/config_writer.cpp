// SPDX-License-Identifier: MIT
#include "sim/server/config_writer.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace excite::sim::server {
namespace {

std::string numbers(const std::vector<double>& xs) {
  std::string out = "[";
  for (std::size_t i = 0; i < xs.size(); ++i) out += (i == 0 ? "" : ", ") + toml_number(xs[i]);
  return out + "]";
}

void entry(std::ostringstream& os, const char* table, const hal::modbus::RegisterEntry& e,
           bool with_function_code) {
  os << "\n[[registers." << table << "]]\n";
  if (!e.name.empty()) os << "name = " << toml_string(e.name) << "\n";
  os << "address = " << e.address << "\n";
  if (with_function_code) os << "function_code = " << e.function_code << "\n";
  os << "type = " << toml_string(e.type) << "\n";
  if (e.type == "float32") {
    os << "word_order = " << toml_string(e.word_order) << "\n";
  } else {
    os << "eng_min = " << toml_number(e.eng_min) << "\neng_max = " << toml_number(e.eng_max)
       << "\n";
    if (e.raw_min) os << "raw_min = " << *e.raw_min << "\n";
    if (e.raw_max) os << "raw_max = " << *e.raw_max << "\n";
  }
}

}  // namespace

std::string toml_number(double x) {
  char buffer[40];
  for (int digits = 1; digits <= 17; ++digits) {  // the shortest text that reads back as x
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, x);
    if (std::strtod(buffer, nullptr) == x) break;
  }
  std::string s(buffer);
  // A whole number a person would write out ("120.0", not "1.2e+02"); exact below 2^53.
  if (s.find_first_of("eE") != std::string::npos && std::abs(x) < 0x1p53 && x == std::trunc(x)) {
    std::snprintf(buffer, sizeof buffer, "%.1f", x);
    s = buffer;
  }
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";  // "n": nan/inf never written
  return s;
}

std::string toml_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

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

  const ServerRegisters& r = config.registers;
  os << "\n[registers]\n";
  if (r.map.heartbeat_address) os << "heartbeat_address = " << *r.map.heartbeat_address << "\n";
  os << "heartbeat_echo_address = " << r.heartbeat_echo_address << "\n";
  os << "heartbeat_echo_function_code = " << r.heartbeat_echo_function_code << "\n";
  if (r.command_address) os << "command_address = " << *r.command_address << "\n";
  if (r.control_address) os << "control_address = " << *r.control_address << "\n";
  os << "write_chunk = " << r.map.write_chunk << "\n";
  os << "read_chunk = " << r.map.read_chunk << "\n";
  for (const auto& e : r.map.setpoints) entry(os, "setpoints", e, false);
  for (const auto& e : r.map.values) entry(os, "values", e, true);
  return os.str();
}

}  // namespace excite::sim::server
