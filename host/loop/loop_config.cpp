// SPDX-License-Identifier: MIT
#include "host/loop/loop_config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "base/config/document.hpp"
#include "base/config/writer.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/app/gateway_config_writer.hpp"
#include "hal/can/can_transport.hpp"
#include "hal/modbus/modbus_transport.hpp"
#include "hal/modbus/register_entry_toml.hpp"
#include "host/design/case_studies.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/can_map.hpp"
#include "sim/server/config_writer.hpp"
#include "sim/server/default_map.hpp"
#include "sim/server/load_closed_loop.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace excite::host {
namespace {

using hal::modbus::EntryKind;
using hal::modbus::format_register_entry;

// A uint16 value of the gateway's that the plant server keeps (heartbeat echo, command).
hal::modbus::RegisterEntry counter(std::uint32_t address, int function_code) {
  hal::modbus::RegisterEntry e;
  e.address = address;
  e.function_code = function_code;
  e.type = "uint16";
  e.eng_min = 0.0;
  e.eng_max = 65535.0;
  return e;
}

// A float32 ABCD value at `address` (FC04 input register, or FC03 holding).
hal::modbus::RegisterEntry float_value(std::uint32_t address, int function_code) {
  hal::modbus::RegisterEntry e;
  e.address = address;
  e.function_code = function_code;
  return e;
}

// The gateway's own settings in every file written here: the plant, the tick, the comm
// guard holding, no real-time priority (the peer is a simulation on the same machine), a
// simulated peer (lock-step allowed) with the plant's own watchdog declared.
app::GatewayConfig gateway_settings(const LoopConfigOptions& opt, const sim::Plant& plant,
                                    double watchdog_s) {
  app::GatewayConfig g;
  g.plant = plant.name() + " (excite-plant)";
  if (opt.period_s > 0.0) g.period_s = opt.period_s;
  g.realtime_priority = 0;
  g.simulator = true;
  if (watchdog_s > 0.0) g.peer_watchdog_s = watchdog_s;
  return g;
}

// [device] over Modbus TCP: excite-plant at --host:--port, unit 1, a generous timeout (the
// machine is shared).
std::string modbus_device(const LoopConfigOptions& opt, const app::GatewayConfig& g) {
  hal::modbus::ModbusDevice device;
  device.host = opt.host;
  device.port = opt.port;
  device.response_timeout_ms = 1000;
  return app::format_device_section("modbus-tcp", g, hal::modbus::format_device_keys(device));
}

app::SetpointSpec setpoint(const std::string& name, const std::string& unit, double range,
                           double center, double max_move, const std::string& readback) {
  app::SetpointSpec s;
  s.name = name;
  s.unit = unit;
  s.min = center - range;
  s.max = center + range;
  s.max_move = max_move;
  s.readback = readback;
  return s;
}

app::ValueSpec value(const std::string& name, const std::string& unit,
                     app::ValueRole role = app::ValueRole::output) {
  app::ValueSpec v;
  v.name = name;
  v.unit = unit;
  v.role = role;
  return v;
}

// An output with --output-range test limits around its baseline y0 (none without them).
app::ValueSpec output(const std::string& name, const std::string& unit, double y0,
                      double output_range) {
  app::ValueSpec v = value(name, unit);
  if (output_range > 0.0) {
    v.test_low = y0 - output_range;
    v.test_high = y0 + output_range;
    v.hysteresis = 0.1 * output_range;
  }
  return v;
}

// The heartbeat echo, and the operator command register: a holding register the gateway
// clears after each command it reads (the acknowledgement: the same code written again is a
// new command).
std::string echo_and_command(const sim::server::ServerRegisters& regs) {
  app::ValueSpec command = value("command", "-", app::ValueRole::command);
  command.acknowledge = true;
  const hal::modbus::RegisterEntry echo =
      counter(regs.heartbeat_echo_address, regs.heartbeat_echo_function_code);
  return app::format_value(value("hb_echo", "-", app::ValueRole::heartbeat_echo),
                           format_register_entry(echo, EntryKind::value)) +
         app::format_value(
             command, format_register_entry(counter(*regs.command_address, 3), EntryKind::value));
}

// Both files read back by the partners' own readers (excite-gateway's configuration with
// hal/modbus's device checks, excite-plant's server configuration): what either refuses,
// loop-config refuses before writing, naming the option that gave the value.
void check_with_partners(const LoopConfigPair& pair) {
  const app::ConfigResult gateway = app::parse_gateway_config(pair.gateway_toml, "gateway.toml");
  if (!gateway.config) {
    const std::string& e = gateway.error;
    const char* option = e.find("device.host") != std::string::npos        ? "--host"
                         : e.find("device.port") != std::string::npos      ? "--port"
                         : e.find("gateway.period_s") != std::string::npos ? "--period-s"
                                                                           : "options";
    throw std::invalid_argument(std::string(option) + ": excite-gateway would refuse " + e);
  }
  try {
    (void)sim::server::parse_server_config(pair.plant_toml, "plant.toml");
  } catch (const std::exception& e) {
    throw std::invalid_argument(std::string("excite-plant would refuse ") + e.what());
  }
}

[[noreturn]] void bad(const std::string& field, double value, const std::string& expected) {
  std::ostringstream os;
  os << field << " = " << value << ", expected " << expected;
  throw std::invalid_argument(os.str());
}

void check(const std::string& field, double value, bool zero_ok) {
  if (!std::isfinite(value) || value < 0.0 || (!zero_ok && value == 0.0)) {
    bad(field, value, zero_ok ? "a finite number >= 0" : "a finite number > 0");
  }
}

std::string gateway_toml(const LoopConfigOptions& opt, const sim::Plant& plant,
                         const sim::server::ServerConfig& server, double range,
                         const std::vector<double>& u0, const std::vector<double>& y0) {
  const auto& map = server.registers.map;
  const auto in_units = plant.input_units();
  const auto out_units = plant.output_units();
  std::string out = "# excite-gateway configuration written by `excite loop-config --plant " +
                    opt.plant +
                    "`,\n# the register map of plant.toml beside it (sim/server/README.md, "
                    "Default register map).\n# Keys: firmware/app/README.md.\n\n";
  const app::GatewayConfig g = gateway_settings(opt, plant, server.plant.watchdog_s);
  out += app::format_gateway_section(g) + modbus_device(opt, g);
  // The map as the plant server serves it, written by the schema's own writer: the same
  // entries, types and word orders on both sides.
  out += "[map]\n" + hal::modbus::format_map_settings(map);
  const double move = opt.max_move > 0.0 ? opt.max_move : 2.0 * range;
  for (std::size_t i = 0; i < map.setpoints.size(); ++i) {
    const auto& e = map.setpoints[i];
    // The gateway's baseline is the register read back at arm, which may sit half a
    // float32 step (|u0|·2⁻²⁴) from u0: the limits allow one step more, so a design that
    // uses exactly ±range is not refused for the register's rounding.
    const double slack = std::abs(u0[i]) * 0x1p-23;
    out += app::format_setpoint(
        setpoint(e.name, in_units[i], range + slack, u0[i], move, e.name + "_sp"),
        format_register_entry(e, EntryKind::setpoint));
  }
  for (std::size_t j = 0; j < map.values.size(); ++j) {
    out += app::format_value(output(map.values[j].name, out_units[j], y0[j], opt.output_range),
                             format_register_entry(map.values[j], EntryKind::value));
  }
  for (std::size_t i = 0; i < map.setpoints.size(); ++i) {
    hal::modbus::RegisterEntry readback = map.setpoints[i];  // its holding register, read back
    readback.function_code = 3;
    out += app::format_value(value(readback.name + "_sp", in_units[i], app::ValueRole::readback),
                             format_register_entry(readback, EntryKind::value));
  }
  return out + echo_and_command(server.registers);
}

// The gateway in closed loop (sim/server/README.md, "Closed loop"): the offsets it writes,
// each read back (verified writes on its own registers), and the controller's registers as
// data.
std::string gateway_closed_loop_toml(const LoopConfigOptions& opt, const sim::Plant& plant,
                                     const sim::server::ServerConfig& server, double range,
                                     const std::string& controller_line) {
  const auto& regs = server.registers;
  const std::uint32_t n = static_cast<std::uint32_t>(plant.inputs());
  const std::uint32_t m = static_cast<std::uint32_t>(plant.outputs());
  const auto in_names = plant.input_names();
  const auto out_names = plant.output_names();
  const auto in_units = plant.input_units();
  const auto out_units = plant.output_units();
  const std::uint32_t w = *regs.offset_address;
  const std::uint32_t r = *regs.controller_address;
  const bool mv = opt.offsets != "setpoint";
  const bool sp = opt.offsets != "mv";
  const double sp_range = opt.output_range > 0.0 ? opt.output_range : range;
  std::string out = "# excite-gateway configuration written by `excite loop-config --plant " +
                    opt.plant + " --controller " +
                    std::filesystem::path(opt.controller).filename().string() + " --offsets " +
                    opt.offsets +
                    "`,\n# the closed-loop register map of plant.toml beside it "
                    "(sim/server/README.md, Closed loop).\n# Keys: firmware/app/README.md.\n\n";
  const app::GatewayConfig g = gateway_settings(opt, plant, server.plant.watchdog_s);
  app::ClosedLoopSpec loop;
  loop.offsets = opt.offsets;
  loop.controller = controller_line;
  loop.controller_timeout_s = opt.controller_timeout_s;
  loop.mv_baseline = server.plant.input_baseline;  // the run log's u = baseline + du
  out += app::format_gateway_section(g) + app::format_closed_loop_section(loop) +
         modbus_device(opt, g) + "[map]\n" + hal::modbus::format_map_settings(regs.map);
  struct Offset {
    std::string name;
    std::string unit;
    std::uint32_t address;
    double range;
  };
  std::vector<Offset> offsets;
  for (std::uint32_t i = 0; mv && i < n; ++i) {
    offsets.push_back({in_names[i] + "_off", in_units[i], w + 2 * i, range});
  }
  for (std::uint32_t j = 0; sp && j < m; ++j) {
    offsets.push_back({out_names[j] + "_spoff", out_units[j], w + 2 * n + 2 * j, sp_range});
  }
  const double move = opt.max_move > 0.0 ? opt.max_move : 2.0 * range;
  for (const Offset& o : offsets) {
    out += app::format_setpoint(
        setpoint(o.name, o.unit, o.range, 0.0, std::max(move, 2.0 * o.range), o.name + "_rb"),
        format_register_entry(float_value(o.address, 16), EntryKind::setpoint));
  }
  const auto data = [&out](const app::ValueSpec& v, const hal::modbus::RegisterEntry& e) {
    out += app::format_value(v, format_register_entry(e, EntryKind::value));
  };
  for (std::size_t j = 0; j < regs.map.values.size(); ++j) {
    data(output(regs.map.values[j].name, out_units[j], server.plant.output_baseline[j],
                opt.output_range),
         regs.map.values[j]);
  }
  for (const Offset& o : offsets)
    data(value(o.name + "_rb", o.unit, app::ValueRole::readback), float_value(o.address, 3));
  out += echo_and_command(regs);
  data(value("mode", "-", app::ValueRole::controller_mode), counter(r + 5 * n + 2 * m, 4));
  for (std::uint32_t i = 0; i < n; ++i) {
    data(value("st_" + in_names[i], "-", app::ValueRole::mv_status),
         counter(r + 4 * n + 2 * m + i, 4));
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    data(value("uc_" + in_names[i], in_units[i], app::ValueRole::controller_move),
         float_value(r + 2 * i, 4));
  }
  for (std::uint32_t i = 0; i < n; ++i) {
    data(value("ua_" + in_names[i], in_units[i], app::ValueRole::applied_mv),
         float_value(r + 2 * n + 2 * i, 4));
  }
  for (std::uint32_t j = 0; j < m; ++j) {
    data(value("ysp_" + out_names[j], out_units[j], app::ValueRole::setpoint_in_force),
         float_value(r + 4 * n + 2 * j, 4));
  }
  return out;
}

// The gateway over CAN: sim/server's default CAN frame map, the same limits as over Modbus.
std::string gateway_can_toml(const LoopConfigOptions& opt, const sim::Plant& plant,
                             const sim::server::ServerConfig& server, double range,
                             const std::vector<double>& u0, const std::vector<double>& y0) {
  const sim::server::CanLoopMap loop = sim::server::default_can_map(
      plant.inputs(), plant.outputs(), plant.input_names(), plant.output_names());
  const auto& map = loop.gateway;
  const auto in_units = plant.input_units();
  const auto out_units = plant.output_units();
  const auto n = map.setpoints.size();
  std::string out = "# excite-gateway configuration written by `excite loop-config --plant " +
                    opt.plant +
                    " --transport can`,\n# the default CAN frame map excite-plant --can serves "
                    "(sim/server/README.md).\n# Keys: firmware/app/README.md; frames: "
                    "hal/README.md.\n\n";
  // CAN has no [device] keys of its own; its settings are the [can] section.
  const app::GatewayConfig g = gateway_settings(opt, plant, server.plant.watchdog_s);
  out += app::format_gateway_section(g) + app::format_device_section("can", g, "");
  hal::can::CanConfig can;
  can.interface = opt.can_interface;
  can.value_timeout_ms = 1000;
  can.map.heartbeat = map.heartbeat;
  out += "[can]\n" + hal::can::format_can_settings(can);
  const double move = opt.max_move > 0.0 ? opt.max_move : 2.0 * range;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = map.setpoints[i];
    const double slack = std::abs(u0[i]) * 0x1p-23;  // float32, as over Modbus
    out += app::format_setpoint(
        setpoint(s.name, in_units[i], range + slack, u0[i], move, s.name + "_sp"),
        hal::can::format_can_entry(s));
  }
  for (std::size_t k = 0; k < map.values.size(); ++k) {
    const auto& s = map.values[k];
    const bool is_output = k < y0.size();
    const bool readback = !is_output && k < y0.size() + n;
    const app::ValueSpec v = is_output ? output(s.name, out_units[k], y0[k], opt.output_range)
                             : readback
                                 ? value(s.name, in_units[k - y0.size()], app::ValueRole::readback)
                                 : value(s.name, "-", app::ValueRole::heartbeat_echo);
    out += app::format_value(v, hal::can::format_can_entry(s));
  }
  return out;
}

// Every number and choice of the command line, by name, before anything is built.
void check_loop_options(const LoopConfigOptions& opt) {
  check("--input-range", opt.input_range, true);
  check("--max-move", opt.max_move, true);
  check("--output-range", opt.output_range, true);
  check("--sample-time-min", opt.sample_time_min, true);
  check("--period-s", opt.period_s, true);
  check("--watchdog-s", opt.watchdog_s, true);
  if (opt.noise_var != -1.0) check("--noise-var", opt.noise_var, true);
  if (opt.port > 65535) bad("--port", opt.port, "a TCP port 0..65535");
  if (!opt.controller.empty() && opt.transport != "modbus-tcp") {
    throw std::invalid_argument("--transport = \"" + opt.transport +
                                "\", expected modbus-tcp with --controller (the CAN frame map "
                                "has no closed-loop frames)");
  }
  if (opt.offsets != "setpoint" && opt.offsets != "mv" && opt.offsets != "both") {
    throw std::invalid_argument("--offsets = \"" + opt.offsets +
                                "\", expected setpoint, mv or both");
  }
  check("--controller-timeout-s", opt.controller_timeout_s, true);
  if (opt.transport != "modbus-tcp" && opt.transport != "can") {
    throw std::invalid_argument("--transport = \"" + opt.transport +
                                "\", expected modbus-tcp or can");
  }
}

// The case study (when the plant has one) gives the defaults: T, noise, input range.
struct LoopDefaults {
  double range = 0.0;
  double sample_time_min = 0.0;
  double noise_var = 0.0;
  bool has_study = false;
  PriorKnowledge prior;
};

LoopDefaults loop_defaults(const LoopConfigOptions& opt) {
  LoopDefaults d{opt.input_range, opt.sample_time_min, opt.noise_var, false, {}};
  const auto studies = case_study_plants();
  d.has_study = std::find(studies.begin(), studies.end(), opt.plant) != studies.end();
  if (d.has_study) {
    d.prior = case_study(opt.plant);
    if (d.range == 0.0) {
      for (const InputSpec& in : d.prior.inputs) d.range = std::max({d.range, -in.min, in.max});
    }
    if (d.sample_time_min == 0.0) d.sample_time_min = d.prior.sample_time_min;
    if (d.noise_var < 0.0) d.noise_var = case_study_noise_variance(opt.plant);
  }
  if (d.range == 0.0) {
    bad("--input-range", 0.0,
        "a range > 0 for plant " + opt.plant + ", which has no case study to take it from");
  }
  if (d.sample_time_min == 0.0) d.sample_time_min = 1.0;
  if (d.noise_var < 0.0) d.noise_var = 0.0;
  return d;
}

}  // namespace

LoopConfigPair make_loop_config(const LoopConfigOptions& opt) {
  check_loop_options(opt);
  const auto plant = sim::make_plant(opt.plant);

  const LoopDefaults defaults = loop_defaults(opt);
  const double range = defaults.range;
  const double sample_time = defaults.sample_time_min;
  const double noise = defaults.noise_var;
  const bool has_study = defaults.has_study;
  const PriorKnowledge& prior = defaults.prior;

  sim::server::ServerConfig server;
  server.plant.tau_high_min = prior.tau_high_min;    // the design's time scales (0 without a
  server.plant.beta = has_study ? prior.beta : 0.0;  // case study), for the plant's run log
  const bool file = opt.plant.size() > 5 && opt.plant.ends_with(".toml");
  if (file) {
    server.plant.file = std::filesystem::absolute(opt.plant).string();
  } else {
    server.plant.library = opt.plant;
  }
  server.plant.sample_time_min = sample_time;
  const Eigen::VectorXd u0 = plant->input_baseline();
  std::vector<double> u0v(u0.data(), u0.data() + u0.size());
  const Eigen::VectorXd y0 = plant->output_baseline();
  std::vector<double> y0v(y0.data(), y0.data() + y0.size());
  server.plant.input_baseline = u0v;
  server.plant.output_baseline = y0v;
  if (noise > 0.0) server.plant.noise_variance = {noise};
  server.plant.noise_seed = opt.seed;
  // The plant's own controller: a heartbeat watchdog and the gateway's input limits (the
  // same numbers as gateway.toml's min/max, float32 slack included).
  // The watchdog outlasts two gateway periods (the tick period, or the sample time without
  // one): a shorter one would trip between writes (issue 28 item 3).
  const double period_s = opt.period_s > 0.0 ? opt.period_s : 60.0 * sample_time;
  server.plant.watchdog_s = opt.watchdog_s > 0.0 ? std::max(opt.watchdog_s, 2.0 * period_s) : 0.0;
  std::vector<std::string> notes;
  if (opt.watchdog_s > 0.0 && server.plant.watchdog_s > opt.watchdog_s) {
    notes.push_back("--watchdog-s " + config::format_number(opt.watchdog_s) + " raised to " +
                    config::format_number(server.plant.watchdog_s) +
                    " s: at least two tick periods of " + config::format_number(period_s) +
                    " s (a shorter watchdog trips between the gateway's writes)");
  }
  const bool closed = !opt.controller.empty();
  for (std::size_t i = 0; i < u0v.size() && !closed; ++i) {  // under a controller: its MV limits
    const double slack = std::abs(u0v[i]) * 0x1p-23;
    server.plant.input_min.push_back(u0v[i] - range - slack);
    server.plant.input_max.push_back(u0v[i] + range + slack);
  }
  server.registers = sim::server::default_registers(
      plant->inputs(), plant->outputs(), plant->input_names(), plant->output_names(), closed);
  std::string controller_line;
  if (closed) {  // refused here, by name, as excite-plant would refuse it
    server.plant.controller = std::filesystem::absolute(opt.controller).string();
    (void)sim::server::load_closed_loop(server.plant.controller, *plant, sample_time);
    const std::string text = config::read_file(server.plant.controller);
    const bool pi = text.find("kind = \"pi\"") != std::string::npos;
    controller_line = std::string(pi ? "pi " : "dmc ") +
                      std::filesystem::path(opt.controller).filename().string();
  }

  LoopConfigPair pair;
  pair.plant_toml = sim::server::format_server_config(
      server, "excite-plant configuration written by `excite loop-config --plant " + opt.plant +
                  "`; its gateway side: gateway.toml");
  pair.gateway_toml = closed ? gateway_closed_loop_toml(opt, *plant, server, range, controller_line)
                      : opt.transport == "can"
                          ? gateway_can_toml(opt, *plant, server, range, u0v, y0v)
                          : gateway_toml(opt, *plant, server, range, u0v, y0v);
  check_with_partners(pair);
  pair.notes = std::move(notes);
  return pair;
}

}  // namespace excite::host
