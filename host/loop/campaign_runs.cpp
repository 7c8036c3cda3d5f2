// SPDX-License-Identifier: MIT
#include "host/loop/campaign_runs.hpp"

#include <utility>

#include "host/design/plan_file.hpp"
#include "host/identify/run_layout.hpp"

namespace excite::host {

namespace fs = std::filesystem;

std::string experiment_folder(int number, const std::string& name) {
  return (number < 10 ? "0" : "") + std::to_string(number) + "-" + name;
}

MeasuredData measured_data(const runlog::RunLog& log, const std::string& name) {
  // identify's flags rule (host/identify/run_layout.hpp), as `excite identify RUN` applies it
  StackedRuns data = stack_runs({&log}, {name}, FlagRule{});
  MeasuredData measured;
  SimulatedRun& run = measured.run;
  run.plant = log.plant;
  run.plan = log.plan;
  run.sample_time_min = data.sample_time_min;
  run.input_names = log.input_names;
  run.output_names = log.output_names;
  run.du = std::move(data.U);
  run.dy = std::move(data.Y);
  measured.layout = std::move(data.layout);
  return measured;
}

MeasuredRun measured_runs_in_the_loop(const std::string& plant, const fs::path& runs,
                                      const LoopPrograms& programs,
                                      const std::function<void(const std::string&)>& say) {
  return [=](const RunRequest& request) {
    LoopRun loop;
    loop.work_dir = runs / experiment_folder(request.number, request.name);
    fs::create_directories(loop.work_dir);
    loop.plan = loop.work_dir / (request.name + ".plan");
    write_plan_file(request.plan, loop.plan);
    loop.config.plant = plant;
    loop.config.noise_var = request.noise_variance;
    loop.config.seed = request.seed;
    loop.programs = programs;
    const LoopResult streamed = stream_in_the_loop(loop);
    const runlog::RunLog& log = streamed.log;
    const MeasuredData run = measured_data(log, streamed.gateway_log.string());
    if (say)
      say(request.name + ": streamed through excite-gateway to excite-plant, " +
          std::to_string(log.rows()) + " ticks in " +
          std::to_string(streamed.seconds).substr(0, 4) + " s (" + streamed.gateway_log.string() +
          ")");
    return run;
  };
}

}  // namespace excite::host
