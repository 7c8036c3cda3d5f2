// SPDX-License-Identifier: MIT
// excite-plant: a simulated plant behind a Modbus TCP (or RTU) server, so the gateway can be tested
// in the loop unchanged. Usage and exit codes: sim/server/README.md and --help.
//
// Exit codes: 0 stopped by SIGTERM/SIGINT; 1 failed while serving (cannot listen, cannot
// write the log's header); 2 bad command line or configuration (nothing was served); 3
// stopped by SIGTERM/SIGINT after its run log could not be written (disk full, file-size
// limit: logging stopped, the log is whole up to its last full row, serving went on).

#include <arpa/inet.h>
#include <net/if.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "base/config/document.hpp"
#include "base/config/error.hpp"
#include "firmware/runlog/format.hpp"
#include "sim/server/default_map.hpp"
#include "sim/server/load_closed_loop.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/plant_server.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"
#include "sim/server/server_overrides.hpp"
#include "sim/server/servers.hpp"

namespace {

using namespace excite::sim::server;

constexpr int kExitBadInput = 2;  // 0, 1 and 3 come from the server (servers.hpp)

volatile std::sig_atomic_t g_stop = 0;

void on_signal(int) {
  g_stop = 1;
}

void install_handlers() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGTERM, &action, nullptr);
  sigaction(SIGINT, &action, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // a vanished client is an error return, not a death
}

[[noreturn]] void bad(const std::string& field, const std::string& value,
                      const std::string& expected) {
  throw excite::config::Error(field, value, expected);
}

// A finite number above (or at, when `zero_ok`) zero, or an error naming the option.
void check_positive(const std::string& option, double x, bool zero_ok, const std::string& what) {
  if (!std::isfinite(x) || x < 0.0 || (!zero_ok && x == 0.0))
    bad(option, excite::config::format_number(x), what);
}

// "ADDR:PORT" → host and port (ADDR an IPv4 address, PORT 0..65535).
void parse_endpoint(const std::string& text, std::string& host, std::uint16_t& port) {
  const auto colon = text.rfind(':');
  const std::string expected = "ADDR:PORT, an IPv4 address and a port 0..65535 (127.0.0.1:1502)";
  if (colon == std::string::npos) bad("--modbus-tcp", "\"" + text + "\"", expected);
  host = text.substr(0, colon);
  const std::string port_text = text.substr(colon + 1);
  in_addr probe{};
  if (inet_pton(AF_INET, host.c_str(), &probe) != 1 || port_text.empty() ||
      port_text.find_first_not_of("0123456789") != std::string::npos || port_text.size() > 5 ||
      std::stoul(port_text) > 65535) {
    bad("--modbus-tcp", "\"" + text + "\"", expected);
  }
  port = static_cast<std::uint16_t>(std::stoul(port_text));
}

struct CommandLine {
  std::string config_path;               // empty: the default register map for --plant
  std::string transport = "modbus-tcp";  // the server, by its name in servers.hpp
  std::string can_interface;             // --can: the interface
  ServerOverrides overrides;             // over the configuration file
  ServeOptions options;                  // transport, clock, log, faults
};

// What the command line gives before it is checked: numbers read wide, checked by name.
struct RawOptions {
  std::string plant_name;
  std::string plant_file;
  std::string modbus_tcp;
  std::string modbus_rtu;
  std::string clock;
  std::uint32_t baud = 0;
  double speedup = 0.0;
  double noise_var = -1.0;
  std::uint64_t seed = 0;
  double sample_time_min = 0.0;
  double sample_time_s = 0.0;
  std::uint64_t faults_after = 0;
  double watchdog_s = 0.0;
  double input_range = 0.0;
  // Request counts: read wide, then checked by name against the control block's 16-bit
  // registers (before: 65536 failed with CLI11's conversion message, no range named).
  long long stall_requests = 0;
  long long drop_requests = 0;
  long long exception_requests = 0;
};

// The plant and its settings: --config, --plant, --plant-file, noise, sample time, the plan,
// the watchdog, the input range, the controller.
void add_plant_options(CLI::App& app, CommandLine& cl, RawOptions& raw) {
  app.add_option("--config", cl.config_path,
                 "register map and plant settings (TOML); default: the register map derived "
                 "from --plant (README, Default register map)")
      ->check(CLI::ExistingFile);
  auto* plant_opt = app.add_option(
      "--plant", raw.plant_name,
      "plant: a library plant, colaA, pilot15, or a plant file ending in .toml (overrides "
      "plant.*)");
  app.add_option("--plant-file", raw.plant_file,
                 "plant file, sim/lti format (overrides plant.file)")
      ->excludes(plant_opt)
      ->check(CLI::ExistingFile);
  app.add_option(
      "--noise-var", raw.noise_var,
      "measurement noise variance on every output, >= 0 (overrides plant.noise_variance)");
  app.add_option("--seed", raw.seed, "noise seed (overrides plant.noise_seed)");
  app.add_option("--sample-time-min", raw.sample_time_min,
                 "model sample time T, minutes > 0 (overrides plant.sample_time_min; default 1)");
  app.add_option("--plan", cl.overrides.plan,
                 "the plan the gateway will stream: refused unless its sample time is the "
                 "plant's (plant.sample_time_min or --sample-time-min)")
      ->check(CLI::ExistingFile);
  app.add_option("--watchdog-s", raw.watchdog_s,
                 "heartbeat watchdog: heartbeat unchanged this long (wall-clock seconds, >= 0; 0 "
                 "off) returns the inputs to the baseline (overrides plant.watchdog_s)");
  app.add_option("--input-range", raw.input_range,
                 "input limits: baseline ± R on every input, > 0; writes outside are refused "
                 "with exception 3 (overrides plant.input_min/input_max)");
  app.add_option("--controller", cl.overrides.controller,
                 "run this controller (sim/control's controller file) in the plant's loop: the "
                 "gateway writes test offsets, the controller the MVs (README, Closed loop; "
                 "overrides plant.controller)")
      ->check(CLI::ExistingFile);
  app.add_option("--controller-log", cl.options.controller_log_path,
                 "closed loop: the controller log (CSV) of every sample and watchdog trip");
}

// How the plant is served: Modbus TCP or RTU or CAN, the clock, the run log.
void add_serving_options(CLI::App& app, CommandLine& cl, RawOptions& raw) {
  ServeOptions& options = cl.options;
  auto* tcp_opt = app.add_option("--modbus-tcp", raw.modbus_tcp,
                                 "serve Modbus TCP on ADDR:PORT (port 0: ephemeral)");
  auto* rtu_opt =
      app.add_option("--modbus-rtu", raw.modbus_rtu, "serve Modbus RTU on a serial DEVICE");
  app.add_option("--baud", raw.baud, "baud rate for --modbus-rtu (default 19200; 8N1, unit 1)")
      ->needs(rtu_opt);
  auto* can_opt =
      app.add_option("--can", cl.can_interface,
                     "serve the default CAN frame map on a SocketCAN interface (e.g. vcan0)");
  tcp_opt->excludes(rtu_opt)->excludes(can_opt);
  rtu_opt->excludes(can_opt);
  auto* clock_opt = app.add_option("--clock", raw.clock, "lockstep | realtime")
                        ->check(CLI::IsMember({"lockstep", "realtime"}));
  app.add_option("--speedup", raw.speedup, "realtime: plant minutes per wall-clock minute, > 0")
      ->needs(clock_opt);
  app.add_option("--host", options.host, "(older form of --modbus-tcp) IPv4 address to listen on")
      ->capture_default_str()
      ->excludes(tcp_opt);
  app.add_option("--port", options.port, "(older form of --modbus-tcp) TCP port; 0: ephemeral")
      ->capture_default_str()
      ->excludes(tcp_opt);
  auto* lockstep = app.add_flag("--lockstep", options.lockstep, "(older form of --clock lockstep)")
                       ->excludes(clock_opt);
  app.add_option("--sample-time-s", raw.sample_time_s,
                 "(older form of --clock realtime --speedup) wall-clock seconds per plant sample")
      ->excludes(lockstep)
      ->excludes(clock_opt);
  app.add_option("--log", options.log_path, "run log (CSV) of every plant sample");
  app.add_option("--idle-timeout-s", options.idle_timeout_s,
                 "close a connection silent this long (never the gateway's), seconds > 0")
      ->capture_default_str();
}

// Faults on purpose, for the gateway's tests (README, Faults).
void add_fault_options(CLI::App& app, CommandLine& cl, RawOptions& raw) {
  ServeOptions& options = cl.options;
  app.add_option("--stall-ms", options.faults.stall_ms, "stall duration for --stall-requests");
  app.add_option("--stall-requests", raw.stall_requests,
                 "answer this many requests only after --stall-ms");
  app.add_option("--freeze-ms", options.freeze_ms,
                 "freeze this long (nothing read, answered or sampled, as a SIGSTOP) after "
                 "--freeze-after requests");
  app.add_option("--freeze-after", options.freeze_after,
                 "requests served normally before the --freeze-ms freeze");
  app.add_option("--drop-requests", raw.drop_requests,
                 "answer this many requests by closing the connection");
  app.add_option("--exception-requests", raw.exception_requests,
                 "answer this many requests with exception 4 (server device failure)");
  app.add_flag("--freeze-echo", options.faults.freeze_echo, "never update the heartbeat echo");
  app.add_option("--faults-after", raw.faults_after,
                 "serve this many requests normally before the faults above apply");
}

// The numbers, checked by name (NaN and negatives included); throws naming the option.
void check_numbers(const CLI::App& app, const RawOptions& raw, ServeOptions& options) {
  if (app.count("--noise-var") > 0)
    check_positive("--noise-var", raw.noise_var, true, "a variance >= 0");
  if (app.count("--sample-time-min") > 0) {
    check_positive("--sample-time-min", raw.sample_time_min, false, "minutes > 0");
  }
  if (app.count("--speedup") > 0) {
    check_positive("--speedup", raw.speedup, false, "a factor > 0 (plant minutes per wall minute)");
    if (raw.clock != "realtime")
      bad("--speedup", excite::config::format_number(raw.speedup), "only with --clock realtime");
  }
  if (app.count("--sample-time-s") > 0) {
    check_positive("--sample-time-s", raw.sample_time_s, false, "seconds > 0");
  }
  check_positive("--idle-timeout-s", options.idle_timeout_s, false, "seconds > 0");
  const auto request_count = [](const char* name, long long value, std::uint16_t& out) {
    if (value < 0 || value > 65535) {
      bad(name, std::to_string(value),
          "a count of requests 0 … 65535 (the control block's 16-bit registers)");
    }
    out = static_cast<std::uint16_t>(value);
  };
  request_count("--stall-requests", raw.stall_requests, options.faults.stall_requests);
  request_count("--drop-requests", raw.drop_requests, options.faults.drop_requests);
  request_count("--exception-requests", raw.exception_requests, options.faults.exception_requests);
  if (app.count("--watchdog-s") > 0) {
    check_positive("--watchdog-s", raw.watchdog_s, true, "wall-clock seconds >= 0 (0: off)");
  }
  if (app.count("--input-range") > 0) {
    check_positive("--input-range", raw.input_range, false, "a range > 0 around the baseline");
  }
}

// The transport's settings, checked by name; throws naming the option.
void check_serving(const CLI::App& app, const RawOptions& raw, CommandLine& cl) {
  ServeOptions& options = cl.options;
  if (!raw.modbus_rtu.empty()) {
    cl.transport = "modbus-rtu";
    options.rtu_device = raw.modbus_rtu;
    if (app.count("--baud") > 0) {
      static const std::vector<std::uint32_t> rates{1200,  2400,  4800,   9600,  19200,
                                                    38400, 57600, 115200, 230400};
      if (std::find(rates.begin(), rates.end(), raw.baud) == rates.end()) {
        bad("--baud", std::to_string(raw.baud),
            "a standard rate: 1200, 2400, 4800, 9600, 19200, 38400, 57600, 115200, 230400");
      }
      options.rtu_baud = static_cast<int>(raw.baud);
    }
  }
  if (!cl.can_interface.empty()) cl.transport = "can";
  if (!cl.can_interface.empty() && cl.can_interface.size() >= IF_NAMESIZE) {
    bad("--can", "\"" + cl.can_interface + "\"",
        "an interface name of 1.." + std::to_string(IF_NAMESIZE - 1) + " characters");
  }
  if (!raw.modbus_tcp.empty()) parse_endpoint(raw.modbus_tcp, options.host, options.port);
  in_addr probe{};
  if (inet_pton(AF_INET, options.host.c_str(), &probe) != 1) {
    bad("--host", "\"" + options.host + "\"", "an IPv4 address such as 127.0.0.1 or 0.0.0.0");
  }
  if (raw.clock == "lockstep") options.lockstep = true;
  if (cl.config_path.empty() && raw.plant_name.empty() && raw.plant_file.empty()) {
    bad("--plant", "(none)", "a plant (library name or .toml file), or --config FILE");
  }
}

// What the command line sets over the configuration file.
void set_overrides(const CLI::App& app, const RawOptions& raw, ServerOverrides& o) {
  o.plant = raw.plant_name;
  o.plant_file = raw.plant_file;
  if (app.count("--noise-var") > 0) o.noise_variance = raw.noise_var;
  if (app.count("--seed") > 0) o.noise_seed = raw.seed;
  if (app.count("--sample-time-min") > 0) o.sample_time_min = raw.sample_time_min;
  if (app.count("--watchdog-s") > 0) o.watchdog_s = raw.watchdog_s;
  if (app.count("--input-range") > 0) o.input_range = raw.input_range;
  if (app.count("--speedup") > 0) o.speedup = raw.speedup;
  if (app.count("--sample-time-s") > 0) o.sample_time_s = raw.sample_time_s;
}

// The command line, its numbers checked by name before anything else (NaN and negatives
// included); an exit code when there is nothing to serve (--help, --version: 0; a bad
// command line: 2).
std::optional<int> parse_command_line(int argc, char** argv, CommandLine& cl) {
  CLI::App app{
      "excite-plant: a simulated plant served over Modbus TCP or RTU for testing excite-gateway "
      "in the loop.\nExit codes: 0 stopped by SIGTERM/SIGINT, 1 failed while serving, 2 bad "
      "command line or configuration (nothing served), 3 stopped after its run log could not be "
      "written (logging stopped, serving went on)."};
  RawOptions raw;
  cl.options.port = 1502;
  add_plant_options(app, cl, raw);
  add_serving_options(app, cl, raw);
  add_fault_options(app, cl, raw);
  app.set_version_flag("--version", "excite-plant " + std::string(excite::runlog::kVersion));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  cl.options.faults_after = raw.faults_after;
  try {
    check_numbers(app, raw, cl.options);
    check_serving(app, raw, cl);
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    return kExitBadInput;
  }
  set_overrides(app, raw, cl.overrides);
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace excite::sim::server;
  // A file-size limit (ulimit -f) must not kill the plant: a log write beyond it fails with
  // EFBIG instead, and logging stops (PlantLog::failure(), Modbus and CAN alike).
  std::signal(SIGXFSZ, SIG_IGN);
  CommandLine cl;
  if (const std::optional<int> rc = parse_command_line(argc, argv, cl)) return *rc;
  const std::string source = cl.config_path.empty() ? std::string("excite-plant") : cl.config_path;
  try {
    ServerConfig config;
    if (!cl.config_path.empty()) config = load_server_config(cl.config_path);
    apply_overrides(config, cl.overrides, source);
    PlantProcess process(load_plant(config.plant, config.base_directory, source), config.plant);
    const excite::sim::Plant& plant = process.plant();
    const bool closed_loop = !config.plant.controller.empty();
    if (cl.config_path.empty()) {
      config.registers = default_registers(plant.inputs(), plant.outputs(), plant.input_names(),
                                           plant.output_names(), closed_loop);
    }
    std::unique_ptr<ClosedLoop> loop;
    const ServerEntry& server = *find_server(cl.transport);
    if (closed_loop) {
      if (!server.closed_loop.empty()) {
        bad("--controller", "\"" + config.plant.controller + "\"",
            "a server with closed-loop registers (" + closed_loop_options() +
                "): " + std::string(server.closed_loop));
      }
      loop = load_closed_loop(config.plant.controller, plant, process.sample_time_min());
    } else if (!cl.options.controller_log_path.empty()) {
      bad("--controller-log", "\"" + cl.options.controller_log_path + "\"",
          "a controller to log (--controller FILE or plant.controller)");
    }
    const ServerLayout layout =
        compile_layout(config, plant.inputs(), plant.outputs(), cl.options.lockstep, source);
    RegisterImage image(layout, process.input_baseline(), process.output_baseline());
    ServeOptions options = cl.options;
    const std::string warning =
        complete_serve_options(options, config, cl.overrides, process, layout, source);
    if (!warning.empty()) std::cerr << "excite-plant: warning: " << warning << "\n";
    if (loop && !options.input_min.empty()) {
      bad(cl.overrides.input_range ? "--input-range" : source + ": plant.input_min",
          cl.overrides.input_range ? excite::config::format_number(*cl.overrides.input_range)
                                   : std::to_string(options.input_min.size()) + " limits",
          "no input limits under a controller (the controller file's [[mv]] min and max bound "
          "the applied MVs)");
    }
    return server.serve({process, image, layout, options, cl.config_path.empty(), cl.can_interface,
                         loop.get(), install_handlers, [] { return g_stop != 0; }});
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    return kExitBadInput;
  }
}
