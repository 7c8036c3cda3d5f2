// SPDX-License-Identifier: MIT
#include "firmware/app/gateway_config.hpp"

#include <toml++/toml.h>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <stdexcept>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "firmware/runlog/format.hpp"
#include "hal/transports/transports.hpp"

namespace excite::app {

namespace {

// A configuration error in the one form of base/config, "FIELD = VALUE, expected …";
// the readers below add the position, parse_gateway_config the file name.
using ConfigError = config::Error;
using config::describe;

void check_keys(const toml::table& table, const std::string& where,
                const std::set<std::string>& allowed) {
  config::Table(table, where, {})
      .only_keys(std::vector<std::string>(allowed.begin(), allowed.end()));
}

std::optional<double> number(const toml::table& t, const std::string& where,
                             const std::string& key) {
  return config::Table(t, where, {}).number(key);
}

double required_number(const toml::table& t, const std::string& where, const std::string& key) {
  auto v = number(t, where, key);
  if (!v) throw ConfigError(where + "." + key, "(missing)", "a number");
  return *v;
}

std::optional<std::int64_t> integer(const toml::table& t, const std::string& where,
                                    const std::string& key, std::int64_t lo, std::int64_t hi) {
  return config::Table(t, where, {}).integer(key, lo, hi);
}

std::optional<std::string> text(const toml::table& t, const std::string& where,
                                const std::string& key) {
  return config::Table(t, where, {}).text(key);
}

const toml::table* table_at(const toml::table& root, const std::string& key, bool required) {
  const toml::node* n = root.get(key);
  if (n == nullptr) {
    if (required) throw ConfigError("[" + key + "]", "(missing)", "a table");
    return nullptr;
  }
  if (!n->is_table()) throw ConfigError(key, describe(*n), "a table [" + key + "]");
  return n->as_table();
}

void parse_gateway(const toml::table& t, GatewayConfig& c) {
  const std::string w = "gateway";
  check_keys(
      t, w,
      {"plant", "period_s", "ramp_s", "resume_dwell_s", "suspend_timeout_s", "confirm_timeout_s",
       "comm_fail_limit", "comm_loss", "heartbeat_max_lag_s", "log_ring", "realtime_priority",
       "readback_lag_ticks", "readback_mismatch_limit", "max_distortion", "log_max_mb"});
  if (auto s = text(t, w, "plant")) {
    if (s->find_first_of("\r\n") != std::string::npos) {
      throw ConfigError(w + ".plant", '"' + *s + '"', "one line of text");
    }
    c.plant = *s;
  }
  // Durations: finite (number()) and within their documented range, so that every one of
  // them converts to ticks without overflow at any accepted period (README "Timing").
  if (auto v = number(t, w, "period_s")) {
    if (!(*v >= kMinPeriodS && *v <= kMaxPeriodS)) {
      throw ConfigError(w + ".period_s", config::format_number(*v),
                        config::format_number(kMinPeriodS) + " … " +
                            config::format_number(kMaxPeriodS) + " seconds");
    }
    c.period_s = *v;
  }
  auto duration = [&](const char* key, double& out) {
    if (auto v = number(t, w, key)) {
      if (!(*v >= 0.0 && *v <= kMaxDurationS)) {
        throw ConfigError(w + "." + key, config::format_number(*v),
                          "0 … " + config::format_number(kMaxDurationS) + " seconds");
      }
      out = *v;
    }
  };
  duration("ramp_s", c.ramp_s);
  duration("resume_dwell_s", c.resume_dwell_s);
  duration("suspend_timeout_s", c.suspend_timeout_s);
  duration("confirm_timeout_s", c.confirm_timeout_s);
  if (!(c.confirm_timeout_s > 0.0)) {
    throw ConfigError(w + ".confirm_timeout_s", config::format_number(c.confirm_timeout_s),
                      "> 0 seconds (how long the gateway keeps confirming the baseline)");
  }
  duration("heartbeat_max_lag_s", c.heartbeat_max_lag_s);
  if (auto v = number(t, w, "log_max_mb")) {
    if (!(*v >= 1e-3 && *v <= 1e6)) {
      throw ConfigError(w + ".log_max_mb", config::format_number(*v), "0.001 … 1e6 MB");
    }
    c.log_max_mb = *v;
  }
  if (auto v = number(t, w, "max_distortion")) {
    if (!(*v >= 0.0 && *v <= 1.0)) {
      throw ConfigError(w + ".max_distortion", config::format_number(*v),
                        "a fraction of the rows 0 … 1 (0: no row may be clamped or rate-limited)");
    }
    c.max_distortion = *v;
  }
  if (auto v = integer(t, w, "comm_fail_limit", 1, 1000000)) {
    c.comm_fail_limit = static_cast<std::uint32_t>(*v);
  }
  if (auto v = integer(t, w, "readback_lag_ticks", 1, engine::kMaxReadbackLag)) {
    c.readback_lag_ticks = static_cast<std::uint32_t>(*v);
  }
  if (auto v = integer(t, w, "readback_mismatch_limit", 0, 1000000)) {
    c.readback_mismatch_limit = static_cast<std::uint32_t>(*v);
  }
  if (auto s = text(t, w, "comm_loss")) {
    if (*s == "hold") {
      c.comm_loss = engine::CommLossAction::hold;
    } else if (*s == "ramp") {
      c.comm_loss = engine::CommLossAction::ramp_to_baseline;
    } else {
      throw ConfigError(w + ".comm_loss", '"' + *s + '"', "\"hold\" or \"ramp\"");
    }
  }
  if (auto v = integer(t, w, "log_ring", 16, 1 << 20)) c.log_ring = static_cast<std::uint32_t>(*v);
  if (auto v = integer(t, w, "realtime_priority", 0, 99))
    c.realtime_priority = static_cast<int>(*v);
}

// [device] transport names a row of hal's table of transports; the transport then reads
// its own [device] keys.
std::unique_ptr<hal::TransportConfig> parse_device(const toml::table& t, GatewayConfig& c) {
  const std::string w = "device";
  const auto s = text(t, w, "transport");
  const hal::TransportEntry* entry =
      s ? hal::find_transport(*s) : &hal::transports().front();  // the first is the default
  if (entry == nullptr) {
    throw ConfigError(w + ".transport", '"' + *s + '"', hal::transport_choices());
  }
  std::unique_ptr<hal::TransportConfig> transport = entry->make();
  if (const toml::node* n = t.get("simulator")) {
    const auto b = n->value_exact<bool>();
    if (!b) throw ConfigError(w + ".simulator", describe(*n), "true or false");
    c.simulator = *b;
  }
  if (auto v = number(t, w, "peer_watchdog_s")) {
    if (!(*v >= 0.0 && *v <= kMaxDurationS)) {
      throw ConfigError(w + ".peer_watchdog_s", config::format_number(*v),
                        "0 … " + config::format_number(kMaxDurationS) + " seconds (0: none)");
    }
    c.peer_watchdog_s = *v;
  }
  std::set<std::string> keys = {"transport", "simulator", "peer_watchdog_s"};
  for (std::string& k : transport->device_keys()) keys.insert(std::move(k));
  check_keys(t, w, keys);
  transport->read_device(config::Table(t, w, {}));
  return transport;
}

// The sections of the file: the chosen transport reads its own; another transport's is
// refused.
void parse_sections(const toml::table& root, hal::TransportConfig& transport) {
  transport.read_sections(config::Table(root, "", {}));
  const std::vector<std::string> own = transport.sections();
  for (const std::string& section : hal::transport_sections()) {
    if (root.get(section) == nullptr || std::find(own.begin(), own.end(), section) != own.end()) {
      continue;
    }
    throw ConfigError(
        section, "a table",
        "no [" + section + "] section with transport = \"" + std::string(transport.name()) + "\"");
  }
}

// The keys an entry may carry: its own plus the transport's mapping keys.
std::set<std::string> entry_keys(std::set<std::string> own, const hal::TransportConfig& transport) {
  for (std::string& k : transport.entry_keys()) own.insert(std::move(k));
  return own;
}

std::string channel_name(const toml::table& t, const std::string& w) {
  auto name = text(t, w, "name");
  if (!name) throw ConfigError(w + ".name", "(missing)", "a name");
  if (!runlog::valid_channel_name(*name)) {
    throw ConfigError(w + ".name", '"' + *name + '"',
                      "letters, digits, '_', '.', '-' (a run-log channel name)");
  }
  return *name;
}

std::string channel_unit(const toml::table& t, const std::string& w) {
  auto unit = text(t, w, "unit");
  if (!unit) return "-";
  if (!runlog::valid_unit(*unit)) {
    throw ConfigError(w + ".unit", '"' + *unit + '"', "a unit without spaces, ',' or '='");
  }
  return *unit;
}

const toml::array& array_of_tables(const toml::table& root, const std::string& key) {
  const toml::node* n = root.get(key);
  if (n == nullptr || !n->is_array()) {
    throw ConfigError(key, n == nullptr ? "(missing)" : describe(*n),
                      "an array of tables [[" + key + "]]");
  }
  return *n->as_array();
}

void parse_setpoints(const toml::table& root, GatewayConfig& c, hal::TransportConfig& transport) {
  const toml::array& list = array_of_tables(root, "setpoints");
  std::size_t i = 0;
  for (const toml::node& node : list) {
    const std::string w = "setpoints[" + std::to_string(i++) + "]";
    if (!node.is_table()) throw ConfigError(w, describe(node), "a table");
    const toml::table& t = *node.as_table();
    check_keys(t, w, entry_keys({"name", "unit", "min", "max", "max_move", "readback"}, transport));
    SetpointSpec s;
    s.name = channel_name(t, w);
    s.unit = channel_unit(t, w);
    s.min = required_number(t, w, "min");
    s.max = required_number(t, w, "max");
    if (s.min > s.max) {
      throw ConfigError(w + ".max", std::to_string(s.max), ">= min = " + std::to_string(s.min));
    }
    s.max_move = required_number(t, w, "max_move");
    if (s.max_move <= 0.0) {
      throw ConfigError(w + ".max_move", std::to_string(s.max_move), "> 0 per tick");
    }
    auto rb = text(t, w, "readback");
    if (!rb) throw ConfigError(w + ".readback", "(missing)", "the name of a readback value");
    s.readback = *rb;
    transport.read_entry(config::Table(t, w, {}), hal::ChannelKind::setpoint, s.name);
    c.setpoints.push_back(s);
  }
  if (c.setpoints.empty() || c.setpoints.size() > engine::kMaxInputs) {
    throw ConfigError("setpoints", std::to_string(c.setpoints.size()) + " entries",
                      "1…" + std::to_string(engine::kMaxInputs));
  }
}

void parse_values(const toml::table& root, GatewayConfig& c, hal::TransportConfig& transport) {
  const toml::array& list = array_of_tables(root, "values");
  std::size_t i = 0;
  for (const toml::node& node : list) {
    const std::string w = "values[" + std::to_string(i++) + "]";
    if (!node.is_table()) throw ConfigError(w, describe(node), "a table");
    const toml::table& t = *node.as_table();
    check_keys(
        t, w,
        entry_keys({"name", "unit", "role", "acknowledge", "test_low", "test_high", "hysteresis"},
                   transport));
    ValueSpec v;
    v.name = channel_name(t, w);
    v.unit = channel_unit(t, w);
    if (auto role = text(t, w, "role")) {
      const std::optional<ValueRole> known = role_of(*role);
      if (!known) {
        throw ConfigError(w + ".role", '"' + *role + '"',
                          "output, readback, heartbeat_echo, command, or in closed loop "
                          "controller_mode, mv_status, controller_move, applied_mv, "
                          "setpoint_in_force");
      }
      v.role = *known;
    }
    if (auto ack = text(t, w, "acknowledge")) {
      if (v.role != ValueRole::command) {
        throw ConfigError(w + ".acknowledge", '"' + *ack + '"',
                          "only on the command value (role = \"command\")");
      }
      if (*ack != "clear" && *ack != "none") {
        throw ConfigError(w + ".acknowledge", '"' + *ack + '"',
                          "\"clear\" (the gateway writes 0 back after each command) or \"none\"");
      }
      v.acknowledge = *ack == "clear";
    }
    v.test_low = number(t, w, "test_low");
    v.test_high = number(t, w, "test_high");
    if (v.test_low.has_value() != v.test_high.has_value()) {
      throw ConfigError(w + (v.test_low ? ".test_high" : ".test_low"), "(missing)",
                        "test_low and test_high together");
    }
    if (v.test_low && v.role != ValueRole::output) {
      throw ConfigError(w + ".test_low", std::to_string(*v.test_low),
                        "test limits on outputs only");
    }
    v.hysteresis = number(t, w, "hysteresis").value_or(0.0);
    if (v.test_low && !(*v.test_low < *v.test_high && v.hysteresis >= 0.0 &&
                        2.0 * v.hysteresis < *v.test_high - *v.test_low)) {
      throw ConfigError(w + ".hysteresis", std::to_string(v.hysteresis),
                        ">= 0 and 2 * hysteresis < test_high - test_low (with test_low < "
                        "test_high)");
    }
    transport.read_entry(config::Table(t, w, {}), hal::ChannelKind::value, v.name);
    c.values.push_back(v);
  }
  if (c.values.empty() || c.values.size() > engine::kMaxValues) {
    throw ConfigError("values", std::to_string(c.values.size()) + " entries",
                      "1…" + std::to_string(engine::kMaxValues));
  }
}

// A setpoint's limits must lie inside what its field encoding carries: the bus would clip a
// setpoint beyond it without the engine knowing.
void check_representable(const GatewayConfig& c, const hal::TransportConfig& transport) {
  const std::vector<hal::CarriedRange> ranges = transport.carried_range(hal::ChannelKind::setpoint);
  for (std::size_t i = 0; i < ranges.size() && i < c.setpoints.size(); ++i) {
    const config::Check v = hal::check_carried(ranges[i], "setpoints[" + std::to_string(i) + "]",
                                               c.setpoints[i].min, c.setpoints[i].max);
    if (!v.ok()) throw ConfigError(v);
  }
}

// Verified writes: each setpoint against the value its baseline is read back from (the
// transport compares their encodings). Runs after the transport's own validation.
void check_readback_encodings(const GatewayConfig& c, const hal::TransportConfig& transport) {
  for (std::size_t i = 0; i < c.setpoints.size(); ++i) {
    const auto& rb = c.setpoints[i].readback;
    const auto it = std::find_if(c.values.begin(), c.values.end(),
                                 [&rb](const ValueSpec& v) { return v.name == rb; });
    if (it == c.values.end()) continue;
    transport.check_readback(i, static_cast<std::size_t>(it - c.values.begin()));
  }
}

// The closed-loop roles: only with [closed_loop]; then one controller_mode, at least one
// mv_status, at most kMaxInputs of each per-channel role, and controller_move/applied_mv
// either absent or one per mv_status.
void check_closed_loop_roles(const GatewayConfig& c) {
  std::size_t mode = 0;
  std::size_t status = 0;
  std::size_t move = 0;
  std::size_t applied = 0;
  std::size_t setpoint = 0;
  for (std::size_t j = 0; j < c.values.size(); ++j) {
    const ValueRole role = c.values[j].role;
    const bool closed = role == ValueRole::controller_mode || role == ValueRole::mv_status ||
                        role == ValueRole::controller_move || role == ValueRole::applied_mv ||
                        role == ValueRole::setpoint_in_force;
    if (closed && !c.closed_loop) {
      throw ConfigError("values[" + std::to_string(j) + "].role", "\"(closed-loop role)\"",
                        "a [closed_loop] table: this role is read back from a running "
                        "controller");
    }
    mode += role == ValueRole::controller_mode;
    status += role == ValueRole::mv_status;
    move += role == ValueRole::controller_move;
    applied += role == ValueRole::applied_mv;
    setpoint += role == ValueRole::setpoint_in_force;
  }
  if (!c.closed_loop) return;
  const std::string n = std::to_string(engine::kMaxInputs);
  if (mode != 1) {
    throw ConfigError("values", std::to_string(mode) + " controller_mode values",
                      "exactly one under [closed_loop] (the controller's mode is watched)");
  }
  if (status < 1 || status > engine::kMaxInputs) {
    throw ConfigError("values", std::to_string(status) + " mv_status values",
                      "1 … " + n + " under [closed_loop] (each MV's status is watched)");
  }
  if ((move != 0 && move != status) || (applied != 0 && applied != status)) {
    throw ConfigError("values",
                      std::to_string(move) + " controller_move, " + std::to_string(applied) +
                          " applied_mv values",
                      "none or one per mv_status value (" + std::to_string(status) + ")");
  }
  const std::size_t baselines = c.closed_loop->mv_baseline.size();
  if (baselines != 0 && baselines != status) {
    throw ConfigError("closed_loop.mv_baseline", std::to_string(baselines) + " numbers",
                      "none or one per mv_status value (" + std::to_string(status) + ")");
  }
  if (setpoint > engine::kMaxInputs) {
    throw ConfigError("values", std::to_string(setpoint) + " setpoint_in_force values",
                      "at most " + n);
  }
}

void cross_check(GatewayConfig& c, const hal::TransportConfig& transport) {
  std::set<std::string> names;
  auto unique = [&names](const std::string& field, const std::string& name) {
    if (!names.insert(name).second) {
      throw ConfigError(field, '"' + name + '"', "a name not used by another setpoint or value");
    }
  };
  for (std::size_t i = 0; i < c.setpoints.size(); ++i) {
    unique("setpoints[" + std::to_string(i) + "].name", c.setpoints[i].name);
  }
  int echoes = 0;
  int commands = 0;
  for (std::size_t j = 0; j < c.values.size(); ++j) {
    unique("values[" + std::to_string(j) + "].name", c.values[j].name);
    if (c.values[j].role == ValueRole::heartbeat_echo && ++echoes > 1) {
      throw ConfigError("values[" + std::to_string(j) + "].role", "\"heartbeat_echo\"",
                        "at most one heartbeat_echo value");
    }
    if (c.values[j].role == ValueRole::command && ++commands > 1) {
      throw ConfigError("values[" + std::to_string(j) + "].role", "\"command\"",
                        "at most one command value");
    }
  }
  for (std::size_t i = 0; i < c.setpoints.size(); ++i) {
    const auto& rb = c.setpoints[i].readback;
    const auto it = std::find_if(c.values.begin(), c.values.end(),
                                 [&rb](const ValueSpec& v) { return v.name == rb; });
    if (it == c.values.end() || it->role != ValueRole::readback) {
      throw ConfigError("setpoints[" + std::to_string(i) + "].readback", '"' + rb + '"',
                        "the name of a value with role = \"readback\"");
    }
  }
  if (std::none_of(c.values.begin(), c.values.end(),
                   [](const ValueSpec& v) { return v.role == ValueRole::output; })) {
    throw ConfigError("values", "no output", "at least one value with role = \"output\"");
  }
  check_closed_loop_roles(c);
  transport.validate();
  check_representable(c, transport);
  check_readback_encodings(c, transport);
}

// [closed_loop] (README "Closed loop"): which offsets the setpoints are, the controller's
// timeout, the log's controller line.
void parse_closed_loop(const toml::table& t, GatewayConfig& c) {
  const std::string w = "closed_loop";
  check_keys(t, w, {"offsets", "controller", "controller_timeout_s", "mv_baseline"});
  ClosedLoopSpec spec;
  if (auto s = text(t, w, "offsets")) {
    if (*s != "mv" && *s != "setpoint" && *s != "both") {
      throw ConfigError(w + ".offsets", '"' + *s + '"',
                        "\"mv\" (MV test offsets), \"setpoint\" (CV setpoint offsets) or \"both\"");
    }
    spec.offsets = *s;
  } else {
    throw ConfigError(w + ".offsets", "(missing)", "\"mv\", \"setpoint\" or \"both\"");
  }
  if (auto s = text(t, w, "controller")) {
    if (s->find_first_of("\r\n") != std::string::npos) {
      throw ConfigError(w + ".controller", '"' + *s + '"', "one line of text");
    }
    spec.controller = *s;
  }
  if (auto v = number(t, w, "controller_timeout_s")) {
    if (!(*v >= 0.0 && *v <= kMaxDurationS)) {
      throw ConfigError(w + ".controller_timeout_s", config::format_number(*v),
                        "0 … " + config::format_number(kMaxDurationS) + " seconds (0: never)");
    }
    spec.controller_timeout_s = *v;
  }
  spec.mv_baseline = config::Table(t, w, {}).numbers("mv_baseline");
  c.closed_loop = spec;
}

// [segments]: how a running gateway takes the next plan segment (README "Plan segments").
void parse_segments(const toml::table& t, GatewayConfig& c) {
  const std::string w = "segments";
  check_keys(t, w, {"period_rows", "preapproved_from", "await_s"});
  if (auto v = integer(t, w, "period_rows", 0, 1 << 24)) {
    c.segment_period_rows = static_cast<std::uint32_t>(*v);
  }
  if (auto s = text(t, w, "preapproved_from")) {
    if (s->empty() || s->find_first_of("\r\n") != std::string::npos) {
      throw ConfigError(w + ".preapproved_from", '"' + *s + '"',
                        "one line of text, not empty (what a pre-approved plan's provenance "
                        "contains)");
    }
    c.segment_preapproved_from = *s;
  }
  if (auto v = number(t, w, "await_s")) {
    if (!(*v >= 0.0 && *v <= kMaxDurationS)) {
      throw ConfigError(w + ".await_s", config::format_number(*v),
                        "0 … " + config::format_number(kMaxDurationS) +
                            " seconds (0: the run ends at the table's end)");
    }
    c.segment_await_s = *v;
  }
}

}  // namespace

namespace {

struct RoleName {
  ValueRole role;
  const char* name;
};

constexpr std::array<RoleName, 9> kRoleNames = {{
    {ValueRole::output, "output"},
    {ValueRole::readback, "readback"},
    {ValueRole::heartbeat_echo, "heartbeat_echo"},
    {ValueRole::command, "command"},
    {ValueRole::controller_mode, "controller_mode"},
    {ValueRole::mv_status, "mv_status"},
    {ValueRole::controller_move, "controller_move"},
    {ValueRole::applied_mv, "applied_mv"},
    {ValueRole::setpoint_in_force, "setpoint_in_force"},
}};

}  // namespace

const char* role_name(ValueRole role) noexcept {
  for (const RoleName& r : kRoleNames) {
    if (r.role == role) return r.name;
  }
  return "output";
}

std::optional<ValueRole> role_of(std::string_view name) noexcept {
  for (const RoleName& r : kRoleNames) {
    if (name == r.name) return r.role;
  }
  return std::nullopt;
}

ConfigResult parse_gateway_config(std::string_view text_in, std::string_view source) {
  ConfigResult result;
  try {
    toml::table root = config::parse(text_in, source);
    GatewayConfig c;
    c.source = std::string(source);
    std::set<std::string> sections = {"gateway", "device",   "setpoints",
                                      "values",  "segments", "closed_loop"};
    for (std::string& section : hal::transport_sections()) sections.insert(std::move(section));
    check_keys(root, "", sections);
    if (const toml::table* g = table_at(root, "gateway", false)) parse_gateway(*g, c);
    if (const toml::table* g = table_at(root, "segments", false)) parse_segments(*g, c);
    if (const toml::table* g = table_at(root, "closed_loop", false)) parse_closed_loop(*g, c);
    std::unique_ptr<hal::TransportConfig> transport =
        parse_device(*table_at(root, "device", true), c);
    parse_sections(root, *transport);
    parse_setpoints(root, c, *transport);
    parse_values(root, c, *transport);
    cross_check(c, *transport);
    c.transport = std::move(transport);
    result.config = std::move(c);
  } catch (const config::Error& e) {
    result.error = e.with_source(source).what();
  }
  return result;
}

ConfigResult load_gateway_config(const std::string& path) {
  std::string text;
  try {
    text = config::read_file(path);  // a regular file, bounded, never a blocking open
  } catch (const config::Error& e) {
    ConfigResult r;
    r.error = e.what();
    return r;
  }
  return parse_gateway_config(text, path);
}

namespace {

// Without a transport (a bus handed over built) an exchange is taken to answer within
// 100 ms, the default response timeout of hal's devices.
constexpr double kHandedOverResponseTimeoutS = 0.1;

// Seconds → ticks of `period`, rounded up; NaN, negative → 0 and beyond uint32 → its maximum
// (never an undefined conversion; check_timing() refuses such values before).
std::uint32_t to_ticks(double seconds, std::chrono::duration<double> period) {
  const double x = std::ceil(std::chrono::duration<double>(seconds) / period - 1e-9);
  if (!(x > 0.0)) return 0;
  if (!(x < 4294967295.0)) return std::numeric_limits<std::uint32_t>::max();
  return static_cast<std::uint32_t>(x);
}

}  // namespace

std::string check_timing(const GatewayConfig& c, std::chrono::duration<double> period) {
  const double p = period.count();
  if (!(p >= kMinPeriodS && p <= kMaxPeriodS)) {
    const std::string field = c.period_s ? "gateway.period_s"
                                         : "the plan's sample time (as the "
                                           "tick period; gateway.period_s "
                                           "unset)";
    return c.source + ": " + field + " = " + config::format_number(p) + " s, expected " +
           config::format_number(kMinPeriodS) + " … " + config::format_number(kMaxPeriodS) +
           " seconds";
  }
  // The peer's own watchdog, when the configuration declares one, must outlast two ticks: a
  // shorter one trips between writes and holds the inputs at the baseline while the log
  // shows the excitation (issue 28 item 3).
  if (c.peer_watchdog_s && *c.peer_watchdog_s > 0.0 && *c.peer_watchdog_s < 2.0 * p) {
    return c.source + ": device.peer_watchdog_s = " + config::format_number(*c.peer_watchdog_s) +
           " s, expected at least two tick periods (" + config::format_number(2.0 * p) +
           " s at a period of " + config::format_number(p) +
           " s): a shorter watchdog returns the inputs to the baseline between the gateway's "
           "writes";
  }
  const struct {
    const char* key;
    double seconds;
    double max_ticks;
  } durations[] = {
      {"gateway.ramp_s", c.ramp_s, static_cast<double>(engine::kMaxDurationTicks)},
      {"gateway.resume_dwell_s", c.resume_dwell_s, static_cast<double>(engine::kMaxDurationTicks)},
      {"gateway.suspend_timeout_s", c.suspend_timeout_s,
       static_cast<double>(engine::kMaxDurationTicks)},
      {"gateway.confirm_timeout_s", c.confirm_timeout_s,
       static_cast<double>(engine::kMaxDurationTicks)},
      {"closed_loop.controller_timeout_s",
       c.closed_loop ? c.closed_loop->controller_timeout_s : 0.0,
       static_cast<double>(engine::kMaxDurationTicks)},
      {"gateway.heartbeat_max_lag_s", c.heartbeat_max_lag_s,
       static_cast<double>(engine::kMaxHeartbeatLagTicks)},
      {"segments.await_s", c.segment_await_s, static_cast<double>(engine::kMaxDurationTicks)},
  };
  for (const auto& d : durations) {
    const double ticks = std::ceil(d.seconds / p - 1e-9);
    if (!std::isfinite(d.seconds) || d.seconds < 0.0 || !(ticks <= d.max_ticks)) {
      return c.source + ": " + d.key + " = " + config::format_number(d.seconds) + " (" +
             config::format_number(ticks) + " ticks of " + config::format_number(p) +
             " s), expected 0 … " + config::format_number(d.max_ticks * p) + " seconds (" +
             config::format_number(d.max_ticks) + " ticks) at this period";
    }
  }
  return {};
}

namespace {

// The values' roles the engine acts on: test limits, the heartbeat echo, the command register.
void map_value_roles(const GatewayConfig& c, engine::EngineConfig& e) {
  for (std::size_t j = 0; j < c.values.size(); ++j) {
    const ValueSpec& v = c.values[j];
    if (v.test_low) {
      e.test[j] = {true, *v.test_low, *v.test_high, v.hysteresis};
    }
    if (v.role == ValueRole::heartbeat_echo) e.heartbeat_echo = static_cast<std::int32_t>(j);
    if (v.role == ValueRole::command) {
      e.command_value = static_cast<std::int32_t>(j);
      e.acknowledge_command = v.acknowledge;
    }
  }
}

// Closed loop: the controller's read-backs, the i-th value of a role for the i-th MV or CV,
// and its timeout in ticks and on the real clock.
void watch_controller(const GatewayConfig& c, std::chrono::duration<double> period,
                      engine::ControllerWatch& w) {
  w.status.fill(engine::kNone);
  w.move.fill(engine::kNone);
  w.applied.fill(engine::kNone);
  w.setpoint.fill(engine::kNone);
  std::uint32_t moves = 0;
  std::uint32_t applied = 0;
  for (std::size_t j = 0; j < c.values.size(); ++j) {
    const auto index = static_cast<std::int32_t>(j);
    switch (c.values[j].role) {
      case ValueRole::controller_mode:
        w.mode = index;
        break;
      case ValueRole::mv_status:
        if (w.mvs < engine::kMaxInputs) w.status[w.mvs++] = index;
        break;
      case ValueRole::controller_move:
        if (moves < engine::kMaxInputs) w.move[moves++] = index;
        break;
      case ValueRole::applied_mv:
        if (applied < engine::kMaxInputs) w.applied[applied++] = index;
        break;
      case ValueRole::setpoint_in_force:
        if (w.cvs < engine::kMaxInputs) w.setpoint[w.cvs++] = index;
        break;
      default:
        break;
    }
  }
  w.timeout_ticks = to_ticks(c.closed_loop->controller_timeout_s, period);
  w.timeout_ns = std::chrono::round<std::chrono::nanoseconds>(
                     std::chrono::duration<double>(c.closed_loop->controller_timeout_s))
                     .count();
}

// Verified writes: the tolerance is the coarser of the two encodings' resolution — one
// raw step of a scaled integer (engineering units), 2^-23 relative for float32.
void set_readback_tolerances(const GatewayConfig& c, engine::EngineConfig& e) {
  e.verify_readbacks = true;
  e.readback_lag_ticks = c.readback_lag_ticks;
  e.readback_mismatch_limit = c.readback_mismatch_limit;
  const std::vector<hal::CarriedRange> sp = carried_ranges(c, hal::ChannelKind::setpoint);
  const std::vector<hal::CarriedRange> va = carried_ranges(c, hal::ChannelKind::value);
  for (std::size_t i = 0; i < c.setpoints.size() && i < sp.size(); ++i) {
    engine::InputLimits& in = e.input[i];
    double abs_tol = sp[i].bounded ? sp[i].count : 0.0;
    bool any_float = !sp[i].bounded;
    if (in.readback >= 0 && static_cast<std::size_t>(in.readback) < va.size()) {
      const hal::CarriedRange& r = va[static_cast<std::size_t>(in.readback)];
      if (r.bounded) abs_tol = std::max(abs_tol, r.count);
      any_float = any_float || !r.bounded;
    }
    in.readback_abs_tol = abs_tol;
    in.readback_rel_tol = any_float ? std::ldexp(1.0, -23) : 0.0;
  }
}

}  // namespace

engine::EngineConfig to_engine_config(const GatewayConfig& c,
                                      std::chrono::duration<double> period) {
  auto ticks = [period](double seconds) { return to_ticks(seconds, period); };
  engine::EngineConfig e;
  e.inputs = static_cast<std::uint32_t>(c.setpoints.size());
  e.values = static_cast<std::uint32_t>(c.values.size());
  for (std::size_t i = 0; i < c.setpoints.size(); ++i) {
    const SetpointSpec& s = c.setpoints[i];
    e.input[i].min = s.min;
    e.input[i].max = s.max;
    e.input[i].max_move = s.max_move;
    for (std::size_t j = 0; j < c.values.size(); ++j) {
      if (c.values[j].name == s.readback) e.input[i].readback = static_cast<std::int32_t>(j);
    }
  }
  map_value_roles(c, e);
  if (c.closed_loop) watch_controller(c, period, e.controller);
  e.ramp_ticks = ticks(c.ramp_s);
  e.segment_period_rows = c.segment_period_rows;
  e.segment_await_ticks = ticks(c.segment_await_s);
  e.resume_dwell_ticks = std::max<std::uint32_t>(1, ticks(c.resume_dwell_s));
  e.suspend_timeout_ticks = ticks(c.suspend_timeout_s);
  // Confirmation: two readbacks of the baseline at least one tick and twice the response
  // timeout apart (a write in flight when the link broke has landed by then).
  const double response_s =
      c.transport ? c.transport->response_timeout_s() : kHandedOverResponseTimeoutS;
  e.confirm_hold_ticks = std::max<std::uint32_t>(1, ticks(2.0 * response_s));
  // At least room for the two readbacks, and for a readback lag plus the mismatch limit (the
  // older window): at long periods 60 s may be a single tick.
  e.confirm_timeout_ticks =
      std::max<std::uint32_t>({ticks(c.confirm_timeout_s), e.confirm_hold_ticks + 1,
                               c.readback_lag_ticks + c.readback_mismatch_limit + 1});
  // The same two timeouts on the real clock, for lock-step (Engine::set_real_time): within
  // the 1e6 s range (check_timing), so the nanoseconds fit.
  const auto ns = [](double seconds) {
    return std::chrono::round<std::chrono::nanoseconds>(std::chrono::duration<double>(seconds))
        .count();
  };
  e.suspend_timeout_ns = ns(c.suspend_timeout_s);
  e.confirm_timeout_ns = ns(c.confirm_timeout_s);
  e.comm_fail_limit = c.comm_fail_limit;
  e.comm_loss = c.comm_loss;
  set_readback_tolerances(c, e);
  if (e.heartbeat_echo != engine::kNone) {
    e.heartbeat_max_lag = c.heartbeat_max_lag_s > 0.0
                              ? std::clamp<std::uint32_t>(ticks(c.heartbeat_max_lag_s), 1,
                                                          engine::kMaxHeartbeatLagTicks)
                              : 3;
  }
  return e;
}

std::vector<hal::CarriedRange> carried_ranges(const GatewayConfig& c, hal::ChannelKind kind) {
  return c.transport ? c.transport->carried_range(kind) : std::vector<hal::CarriedRange>();
}

std::vector<int> output_indices(const GatewayConfig& c) {
  std::vector<int> out;
  for (std::size_t j = 0; j < c.values.size(); ++j) {
    if (c.values[j].role == ValueRole::output) out.push_back(static_cast<int>(j));
  }
  return out;
}

plan::Excitation streamed_excitation(const GatewayConfig& c) {
  if (!c.closed_loop) return plan::Excitation::open_loop;
  if (c.closed_loop->offsets == "setpoint") return plan::Excitation::setpoint;
  if (c.closed_loop->offsets == "mv") return plan::Excitation::mv;
  return plan::Excitation::open_loop;  // "both": no closed-loop plan kind carries both
}

}  // namespace excite::app
