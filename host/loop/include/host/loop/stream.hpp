// SPDX-License-Identifier: MIT
#pragma once
// A plan streamed as it runs in the field: the real excite-gateway process streams it over
// Modbus TCP on loopback to the real excite-plant process, in lock-step (the plant owns the
// clock), through a configuration pair from make_loop_config. What comes back is the
// gateway's own run log. The engineer's main job (`excite campaign --loop`) and the
// case study go through here, so what they report is what the gateway did.

#include <chrono>
#include <filesystem>
#include <string>

#include "firmware/runlog/reader.hpp"
#include "host/loop/loop_config.hpp"

namespace excite::host {

struct LoopPrograms {
  std::filesystem::path plant_server;  // excite-plant
  std::filesystem::path gateway;       // excite-gateway
};

/// excite-plant and excite-gateway beside the running program (one build's bin/ folder).
/// Throws std::runtime_error naming a program that is not there.
LoopPrograms programs_beside_this_one();

struct LoopRun {
  std::filesystem::path plan;      // the plan file to stream
  std::filesystem::path work_dir;  // gets plant.toml, gateway.toml, the logs, the stderr files
  LoopConfigOptions config;        // plant, noise, seed, limits (the port is the server's)
  LoopPrograms programs;
  std::chrono::seconds timeout{600};  // for the whole stream
};

struct LoopResult {
  runlog::RunLog log;                 // the gateway's run log (work_dir/run.csv)
  std::filesystem::path gateway_log;  // work_dir/run.csv
  std::filesystem::path plant_log;    // work_dir/plant.csv: every sample the plant took
                                      // (closed loop: also work_dir/controller.csv, the
                                      // plant's controller log, sim/server/README.md)
  std::string gateway_summary;        // the gateway's last stderr line
  double seconds = 0.0;               // wall time of the stream
};

/// Starts the plant server on an ephemeral loopback port at the plan's sample time (its
/// header's; `run.config.sample_time_min` is not used) with --plan, so the plant refuses a
/// plan at another T; streams the plan through the gateway with --start --clock lockstep,
/// waits for both to finish. Throws
/// std::runtime_error when either program fails (exit code and its last stderr line) or
/// the timeout passes, and when the gateway's log is not a valid run log.
LoopResult stream_in_the_loop(const LoopRun& run);

}  // namespace excite::host
