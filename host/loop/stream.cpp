// SPDX-License-Identifier: MIT
#include "host/loop/stream.hpp"

#include <unistd.h>

#include <csignal>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "host/design/plan_file.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/child_process.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::string last_line(const std::string& text) {
  const auto end = text.find_last_not_of('\n');
  if (end == std::string::npos) return "";
  const auto start = text.rfind('\n', end);
  return text.substr(start == std::string::npos ? 0 : start + 1,
                     end - (start == std::string::npos ? 0 : start + 1) + 1);
}

[[noreturn]] void failed(const ChildProcess& child, const std::string& what) {
  throw std::runtime_error(child.name() + " " + what + ": " + last_line(child.stderr_text()));
}

}  // namespace

LoopPrograms programs_beside_this_one() {
  const fs::path self = fs::read_symlink("/proc/self/exe");
  LoopPrograms p{self.parent_path() / "excite-plant", self.parent_path() / "excite-gateway"};
  for (const fs::path& program : {p.plant_server, p.gateway}) {
    if (access(program.c_str(), X_OK) != 0) {
      throw std::runtime_error(program.string() +
                               ": not found beside this program (build the whole project)");
    }
  }
  return p;
}

LoopResult stream_in_the_loop(const LoopRun& run) {
  const auto start = std::chrono::steady_clock::now();
  fs::create_directories(run.work_dir);
  LoopResult result;
  result.gateway_log = run.work_dir / "run.csv";
  result.plant_log = run.work_dir / "plant.csv";
  const fs::path plant_toml = run.work_dir / "plant.toml";
  const fs::path gateway_toml = run.work_dir / "gateway.toml";

  // The plant steps at the sample time of the plan being streamed (its header's), not at
  // one looked up by the plant's name; excite-plant --plan refuses a plan at another T.
  LoopConfigOptions config = run.config;
  config.sample_time_min = read_plan_file(run.plan)->meta.sample_time_min;
  // The plant side first: it picks its port; then the gateway side for that port.
  write_whole_file(plant_toml, make_loop_config(config).plant_toml);
  std::vector<std::string> plant_args = {
      "--config", plant_toml.string(), "--modbus-tcp", config.host + ":0",
      "--clock",  "lockstep",          "--log",        result.plant_log.string()};
  if (config.controller.empty()) {
    plant_args.insert(plant_args.end(), {"--plan", run.plan.string()});
  } else {
    // Closed loop: excite-plant --plan reads open-loop plans only (it would apply the table
    // as MV moves); plant.toml has the plan's sample time from its header all the same. What
    // the plant's controller did, per sample, goes to its controller log.
    plant_args.insert(plant_args.end(),
                      {"--controller-log", (run.work_dir / "controller.csv").string()});
  }
  ChildProcess plant(run.programs.plant_server, plant_args, run.work_dir / "plant.stderr");
  const auto listening = plant.read_line(10s);
  const std::string prefix = "listening ";
  if (!listening || listening->rfind(prefix, 0) != 0) failed(plant, "did not start");
  config.port =
      static_cast<std::uint32_t>(std::stoul(listening->substr(listening->rfind(':') + 1)));
  write_whole_file(gateway_toml, make_loop_config(config).gateway_toml);

  ChildProcess gateway(run.programs.gateway,
                       {"--config", gateway_toml.string(), "--plan", run.plan.string(), "--log",
                        result.gateway_log.string(), "--start", "--clock", "lockstep"},
                       run.work_dir / "gateway.stderr");
  const auto rc = gateway.wait(run.timeout);
  if (!rc) {
    gateway.stop(SIGTERM, 10s);
    failed(gateway, "did not finish within " + std::to_string(run.timeout.count()) + " s");
  }
  if (*rc != 0) failed(gateway, "exited with " + std::to_string(*rc));
  result.gateway_summary = last_line(gateway.stderr_text());
  const auto plant_rc = plant.stop(SIGTERM, 10s);
  if (plant_rc.value_or(-1) != 0) failed(plant, "did not stop cleanly");

  runlog::ReadResult read =
      runlog::read_run_log(result.gateway_log.string(), limited_read_options());
  if (!read.ok()) throw std::runtime_error(read.error->to_string());
  result.log = std::move(read.log);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace excite::host
