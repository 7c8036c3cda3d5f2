// SPDX-License-Identifier: MIT
// excite-plant: a simulated plant behind a Modbus TCP server, so the gateway can be tested
// in the loop unchanged. Usage and exit codes: sim/server/README.md and --help.
//
// Exit codes: 0 stopped by SIGTERM/SIGINT; 1 failed while serving (cannot listen, log
// write failed); 2 bad command line or configuration (nothing was served).

#include <arpa/inet.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <exception>
#include <iostream>
#include <stdexcept>

#include "sim/server/plant_process.hpp"
#include "sim/server/plant_server.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace {

constexpr int kExitStopped = 0;
constexpr int kExitServeFailed = 1;
constexpr int kExitBadInput = 2;

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

}  // namespace

int main(int argc, char** argv) {
  using namespace excite::sim::server;
  CLI::App app{
      "excite-plant: a simulated plant served over Modbus TCP for testing excite-gateway in "
      "the loop.\nExit codes: 0 stopped by SIGTERM/SIGINT, 1 failed while serving, 2 bad "
      "command line or configuration (nothing served)."};
  std::string config_path;
  std::string plant_name;
  std::string plant_file;
  ServeOptions options;
  options.port = 1502;
  double sample_time_s = 0.0;
  std::uint64_t faults_after = 0;
  app.add_option("--config", config_path, "register map and plant settings (TOML)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* plant_opt =
      app.add_option("--plant", plant_name, "library plant by name (overrides plant.library)");
  app.add_option("--plant-file", plant_file, "plant file, sim/lti format (overrides plant.file)")
      ->excludes(plant_opt)
      ->check(CLI::ExistingFile);
  app.add_option("--host", options.host, "IPv4 address to listen on")->capture_default_str();
  app.add_option("--port", options.port, "TCP port; 0: ephemeral (printed on stdout)")
      ->capture_default_str();
  auto* lockstep = app.add_flag("--lockstep", options.lockstep,
                                "one plant sample per heartbeat change (deterministic)");
  app.add_option("--sample-time-s", sample_time_s,
                 "wall-clock seconds per plant sample (free-running); default: real time, "
                 "60 x plant.sample_time_min")
      ->check(CLI::PositiveNumber)
      ->excludes(lockstep);
  app.add_option("--log", options.log_path, "run log (CSV) of every plant sample");
  app.add_option("--stall-ms", options.faults.stall_ms, "stall duration for --stall-requests");
  app.add_option("--stall-requests", options.faults.stall_requests,
                 "answer this many requests only after --stall-ms");
  app.add_option("--drop-requests", options.faults.drop_requests,
                 "answer this many requests by closing the connection");
  app.add_option("--exception-requests", options.faults.exception_requests,
                 "answer this many requests with exception 4 (server device failure)");
  app.add_flag("--freeze-echo", options.faults.freeze_echo, "never update the heartbeat echo");
  app.add_option("--faults-after", faults_after,
                 "serve this many requests normally before the faults above apply");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitBadInput;
  }
  options.faults_after = faults_after;
  in_addr probe{};
  if (inet_pton(AF_INET, options.host.c_str(), &probe) != 1) {
    std::cerr << "excite-plant: --host = \"" << options.host
              << "\": expected an IPv4 address such as 127.0.0.1 or 0.0.0.0\n";
    return kExitBadInput;
  }

  try {
    ServerConfig config = load_server_config(config_path);
    if (!plant_name.empty()) {
      config.plant.library = plant_name;
      config.plant.file.clear();
    }
    if (!plant_file.empty()) {
      config.plant.file = std::filesystem::absolute(plant_file).string();
      config.plant.library.clear();
    }
    const excite::sim::PlantDefinition plant =
        load_plant(config.plant, config.base_directory, config_path);
    const ServerLayout layout =
        compile_layout(config, plant.g.inputs(), plant.g.outputs(), options.lockstep, config_path);
    PlantProcess process(plant.g, config.plant);
    RegisterImage image(layout, process.input_baseline(), process.output_baseline());
    options.sample_time_s = sample_time_s > 0.0 ? sample_time_s : 60.0 * process.sample_time_min();
    options.plant_description =
        plant.name.empty() ? config.plant.file : plant.name + " (excite-plant)";
    options.input_names = plant.g.input_names();
    options.output_names = plant.g.output_names();

    std::unique_ptr<PlantServer> server;
    try {
      server = std::make_unique<PlantServer>(process, image, options);
    } catch (const std::exception& e) {
      std::cerr << "excite-plant: " << e.what() << "\n";
      return kExitServeFailed;
    }
    install_handlers();
    std::printf("listening %s:%u\n", options.host.c_str(), static_cast<unsigned>(server->port()));
    std::fflush(stdout);
    std::cerr << "excite-plant: " << options.plant_description << ", " << plant.g.inputs()
              << " inputs, " << plant.g.outputs() << " outputs, T = " << process.sample_time_min()
              << " min, "
              << (options.lockstep ? std::string("lock-step")
                                   : std::to_string(options.sample_time_s) + " s per sample")
              << "\n";
    try {
      server->run([] { return g_stop != 0; });
    } catch (const std::exception& e) {
      std::cerr << "excite-plant: " << e.what() << "\n";
      return kExitServeFailed;
    }
    std::cerr << "excite-plant: stopped after " << process.samples() << " samples, "
              << server->requests() << " requests\n";
    return kExitStopped;
  } catch (const std::exception& e) {
    std::cerr << "excite-plant: " << e.what() << "\n";
    return kExitBadInput;
  }
}
