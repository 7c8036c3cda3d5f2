// SPDX-License-Identifier: MIT
// excite loop-config --plant NAME [--transport modbus-tcp|can] [--interface IFACE]
//                    [--host ADDR] [--port P] [--input-range R] [--max-move M]
//                    [--output-range R] [--sample-time-min T | --plan PLAN] [--noise-var V]
//                    [--seed S] [--controller FILE [--offsets setpoint|mv|both]
//                    [--controller-timeout-s S]] -o DIR
//
// One register map for both sides of the loop: writes DIR/plant.toml (excite-plant's
// configuration) and DIR/gateway.toml (excite-gateway's), both made by host/loop's
// make_loop_config from sim/server's default register map.

#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/plan_file.hpp"
#include "host/loop/loop_config.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::cli {
namespace {

struct LoopConfigCommand {
  LoopConfigOptions config;
  std::string plan;  // --plan: the plant's sample time is this plan's
  std::string output_dir;
};

void run(const LoopConfigCommand& command) {
  LoopConfigCommand cmd = command;
  if (!cmd.plan.empty())
    cmd.config.sample_time_min = read_plan_file(cmd.plan)->meta.sample_time_min;
  const LoopConfigPair pair = make_loop_config(cmd.config);
  for (const std::string& note : pair.notes) std::cerr << "excite loop-config: " << note << "\n";
  const std::filesystem::path dir(cmd.output_dir);
  std::filesystem::create_directories(dir);
  const auto plant_path = dir / "plant.toml";
  const auto gateway_path = dir / "gateway.toml";
  // The pair is one register map: both written before either is renamed into place.
  WholeFile plant(plant_path), gateway(gateway_path);
  plant.write(pair.plant_toml);
  gateway.write(pair.gateway_toml);
  plant.commit();
  gateway.commit();
  const auto& c = cmd.config;
  std::cout << "wrote " << plant_path.string() << " and " << gateway_path.string() << "\n"
            << "  excite-plant --config " << plant_path.string()
            << (c.transport == "can" ? " --can " + c.can_interface
                                     : " --modbus-tcp " + c.host + ":" + std::to_string(c.port))
            << (cmd.plan.empty() ? "" : " --plan " + cmd.plan) << " --clock lockstep\n"
            << "  excite-gateway --config " << gateway_path.string() << " --plan "
            << (cmd.plan.empty() ? std::string("PLAN") : cmd.plan)
            << " --log RUN.csv --start --clock lockstep\n";
}

}  // namespace

void add_loop_config_command(CLI::App& app) {
  auto opt = std::make_shared<LoopConfigCommand>();
  CLI::App* cmd = app.add_subcommand(
      "loop-config",
      "Write a matching excite-plant and excite-gateway configuration (one register map)");
  cmd->add_option("--plant", opt->config.plant,
                  "plant: library name, colaA, pilot15, or a plant file (.toml)")
      ->required();
  cmd->add_option("--host", opt->config.host, "address the gateway connects to")
      ->capture_default_str();
  cmd->add_option("--port", opt->config.port, "TCP port of the plant server")
      ->capture_default_str();
  cmd->add_option("--transport", opt->config.transport,
                  "modbus-tcp, or can: the gateway speaks the default CAN frame map "
                  "(excite-plant --can)")
      ->capture_default_str()
      ->check(CLI::IsMember({"modbus-tcp", "can"}));
  cmd->add_option("--interface", opt->config.can_interface,
                  "SocketCAN interface for --transport can")
      ->capture_default_str();
  cmd->add_option("--input-range", opt->config.input_range,
                  "setpoint limits: baseline +- this on every input (default: the case "
                  "study's, 2 amplitudes)")
      ->check(finite_non_negative());
  cmd->add_option("--max-move", opt->config.max_move,
                  "largest setpoint change per tick (default: 2 x the input range)")
      ->check(finite_non_negative());
  cmd->add_option("--output-range", opt->config.output_range,
                  "test limits on every output: baseline +- this (default: none)")
      ->check(finite_non_negative());
  auto* sample_time = cmd->add_option("--sample-time-min", opt->config.sample_time_min,
                                      "plant sample time, minutes (default: the case study's)")
                          ->check(finite_non_negative());
  cmd->add_option("--plan", opt->plan,
                  "the plan to be streamed: the plant's sample time is its own (excite-plant "
                  "--plan refuses one at another)")
      ->check(CLI::ExistingFile)
      ->excludes(sample_time);
  cmd->add_option("--noise-var", opt->config.noise_var,
                  "measurement noise variance (default: the case study's)")
      ->check(finite_non_negative());
  cmd->add_option("--seed", opt->config.seed, "noise seed")->capture_default_str();
  cmd->add_option("--period-s", opt->config.period_s,
                  "gateway tick period, seconds (default: the plan's sample time; shorter "
                  "compresses time in tests)")
      ->check(finite_non_negative());
  cmd->add_option("--watchdog-s", opt->config.watchdog_s,
                  "the plant's heartbeat watchdog, wall-clock seconds (0: off)")
      ->capture_default_str()
      ->check(finite_non_negative());
  auto* controller =
      cmd->add_option("--controller", opt->config.controller,
                      "closed loop: the controller file excite-plant runs (plant.controller); "
                      "the gateway writes test offsets (sim/server/README.md, Closed loop)")
          ->check(CLI::ExistingFile);
  cmd->add_option("--offsets", opt->config.offsets,
                  "closed loop: which offsets the gateway writes: setpoint (CV setpoint "
                  "offsets), mv (MV test offsets) or both")
      ->capture_default_str()
      ->check(CLI::IsMember({"setpoint", "mv", "both"}))
      ->needs(controller);
  cmd->add_option("--controller-timeout-s", opt->config.controller_timeout_s,
                  "closed loop: suspended for the controller this long aborts the test (0: never)")
      ->capture_default_str()
      ->check(finite_non_negative())
      ->needs(controller);
  cmd->add_option("-o,--output", opt->output_dir, "directory for plant.toml and gateway.toml")
      ->required();
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
