// SPDX-License-Identifier: MIT
#include "firmware/app/gateway_config_writer.hpp"

#include "base/config/writer.hpp"

namespace excite::app {

namespace {

using config::toml_number;
using config::toml_string;

std::string line(const char* key, const std::string& value) {
  return std::string(key) + " = " + value + "\n";
}

std::string number_line(const char* key, double value) {
  return line(key, toml_number(value));
}

std::string count_line(const char* key, std::uint64_t value) {
  return line(key, std::to_string(value));
}

// A counter or a code: its value has no unit (the reader's default "-" is left unwritten).
bool is_code(ValueRole role) noexcept {
  return role == ValueRole::heartbeat_echo || role == ValueRole::command ||
         role == ValueRole::controller_mode || role == ValueRole::mv_status;
}

// What a role's codes mean, beside its key, where the value is a code.
const char* role_comment(ValueRole role) noexcept {
  switch (role) {
    case ValueRole::command:
      return "   # 1 start, 2 suspend, 3 resume, 4 abort, 5 approve";
    case ValueRole::controller_mode:
      return "   # 0 off, 1 control, 2 test, 3 suspended";
    default:
      return "";
  }
}

}  // namespace

std::string format_gateway_section(const GatewayConfig& c) {
  const GatewayConfig d;  // the reader's defaults
  std::string out = "[gateway]\n" + line("plant", toml_string(c.plant));
  if (c.period_s) out += number_line("period_s", *c.period_s);
  out += count_line("comm_fail_limit", c.comm_fail_limit);
  out += line("comm_loss", c.comm_loss == engine::CommLossAction::hold ? "\"hold\"" : "\"ramp\"");
  out += count_line("realtime_priority", static_cast<std::uint64_t>(c.realtime_priority));
  const auto seconds = [&out](const char* key, double value, double fallback) {
    if (value != fallback) out += number_line(key, value);
  };
  seconds("ramp_s", c.ramp_s, d.ramp_s);
  seconds("resume_dwell_s", c.resume_dwell_s, d.resume_dwell_s);
  seconds("suspend_timeout_s", c.suspend_timeout_s, d.suspend_timeout_s);
  seconds("confirm_timeout_s", c.confirm_timeout_s, d.confirm_timeout_s);
  seconds("heartbeat_max_lag_s", c.heartbeat_max_lag_s, d.heartbeat_max_lag_s);
  seconds("log_max_mb", c.log_max_mb, d.log_max_mb);
  seconds("max_distortion", c.max_distortion, d.max_distortion);
  if (c.readback_lag_ticks != d.readback_lag_ticks)
    out += count_line("readback_lag_ticks", c.readback_lag_ticks);
  if (c.readback_mismatch_limit != d.readback_mismatch_limit)
    out += count_line("readback_mismatch_limit", c.readback_mismatch_limit);
  if (c.log_ring != d.log_ring) out += count_line("log_ring", c.log_ring);
  return out + "\n";
}

std::string format_closed_loop_section(const ClosedLoopSpec& c) {
  std::string out = "[closed_loop]\n" + line("offsets", toml_string(c.offsets)) +
                    line("controller", toml_string(c.controller)) +
                    number_line("controller_timeout_s", c.controller_timeout_s);
  if (!c.mv_baseline.empty()) {
    std::string list;
    for (const double u : c.mv_baseline) list += (list.empty() ? "" : ", ") + toml_number(u);
    out += line("mv_baseline", "[" + list + "]");
  }
  return out + "\n";
}

std::string format_device_section(std::string_view transport, const GatewayConfig& c,
                                  const std::string& transport_keys) {
  std::string out = "[device]\n" + line("transport", toml_string(std::string(transport)));
  if (c.simulator)
    out += "simulator = true   # the peer is a simulated plant: --clock lockstep allowed\n";
  out += transport_keys;
  if (c.peer_watchdog_s) {
    out += "peer_watchdog_s = " + toml_number(*c.peer_watchdog_s) +
           "   # the peer's own heartbeat watchdog: at least two tick periods\n";
  }
  return out + "\n";
}

std::string format_setpoint(const SetpointSpec& s, const std::string& mapping) {
  std::string out = "\n[[setpoints]]\n" + line("name", toml_string(s.name)) +
                    line("unit", toml_string(s.unit)) + mapping + number_line("min", s.min) +
                    number_line("max", s.max) + number_line("max_move", s.max_move);
  if (!s.readback.empty()) out += line("readback", toml_string(s.readback));
  return out;
}

std::string format_value(const ValueSpec& v, const std::string& mapping) {
  std::string out = "\n[[values]]\n" + line("name", toml_string(v.name));
  if (!is_code(v.role) || v.unit != "-") out += line("unit", toml_string(v.unit));
  if (v.role != ValueRole::output) {
    out += "role = \"" + std::string(role_name(v.role)) + "\"" + role_comment(v.role) + "\n";
  }
  if (v.acknowledge) out += "acknowledge = \"clear\"   # 0 written back after each\n";
  out += mapping;
  if (v.test_low) out += number_line("test_low", *v.test_low);
  if (v.test_high) out += number_line("test_high", *v.test_high);
  if (v.test_low || v.test_high) out += number_line("hysteresis", v.hysteresis);
  return out;
}

}  // namespace excite::app
