// SPDX-License-Identifier: MIT
#include "host/loop/closed_loop_campaign.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <stdexcept>
#include <string>

#include "firmware/runlog/format.hpp"
#include "host/campaign/scored_fit.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"
#include "host/design/table.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/run_layout.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/identify/segments.hpp"
#include "host/loop/campaign_runs.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/parallel.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

// Rows where any MV was not free: clamped, wound up or in manual (the run log's st_ columns).
std::size_t mv_limited_rows(const runlog::RunLog& log) {
  std::size_t rows = 0;
  for (std::size_t k = 0; k < log.rows(); ++k) {
    bool limited = false;
    for (const auto& st : log.closed_loop.st) limited |= st[k] != runlog::MvState::ok;
    rows += limited ? 1U : 0U;
  }
  return rows;
}

// A closed-loop run in process, as `excite simulate PLAN --controller FILE` makes it.
SimulatedRun run_in_process(const ClosedLoopCampaignOptions& o, const plan::Plan& p,
                            const std::string& label, double noise_variance, std::uint64_t seed) {
  const sim::control::ControllerFile file = sim::control::load_controller_file(o.controller);
  if (!file.model.model_file.empty()) {
    throw std::invalid_argument("controller model.model_file = " + file.model.model_file +
                                ", expected model.plant for a campaign");
  }
  const auto model = sim::control::load_model(file);
  const auto plant = sim::make_plant(o.plant);
  const Eigen::MatrixXd g0 = plant->static_gain();
  const auto controller = sim::control::make_controller(file, *model, &g0);
  ClosedLoopOptions loop;
  loop.excitation =
      o.design.excitation == "mv" ? runlog::Excitation::mv : runlog::Excitation::setpoint;
  set_controller(loop, file, fs::path(o.controller).filename().string());
  SimulationOptions sim;
  sim.noise_variance = noise_variance;
  sim.seed = seed;
  SimulatedRun run = simulate_closed_loop(make_table(p.recipe), label, p.meta.sample_time_min,
                                          *plant, *controller, loop, sim);
  run.time_scales = {p.meta.tau_high_min, p.meta.beta, p.meta.switch_time_min};
  run.producer = "excite campaign " + std::string(runlog::kVersion);
  return run;
}

// The rows of a v4 log as `excite identify LOG` takes them: the flags rule, the warm-up.
StackedRuns stack_log(const runlog::RunLog& log, const std::string& name) {
  FlagRule rule;
  rule.warm_up_min = IdentifyOptions{}.max_delay_min;
  return stack_runs({&log}, {name}, rule);
}

// `excite identify LOG` on a v4 log stacked by stack_log: the time-constant bound β·τ_H of
// the log, then both closed-loop methods.
ClosedLoopIdentification identify_log(const runlog::RunLog& log, const StackedRuns& data,
                                      const std::string& name) {
  IdentifyOptions options;
  if (log.time_scales.beta > 0.0 && log.time_scales.tau_high_min > 0.0)
    options.max_time_constant_min = log.time_scales.beta * log.time_scales.tau_high_min;
  const runlog::ClosedLoopLog& cl = log.closed_loop;
  if (!cl.closed || static_cast<std::size_t>(data.U.rows()) != log.rows()) {
    throw std::invalid_argument(name +
                                ": loop = open (or rows dropped), expected a closed-loop "
                                "run, run-log v4, every row kept");
  }
  Eigen::MatrixXd R(data.U.rows(), static_cast<Eigen::Index>(cl.r.size()));
  for (std::size_t c = 0; c < cl.r.size(); ++c) {
    R.col(static_cast<Eigen::Index>(c)) =
        Eigen::Map<const Eigen::VectorXd>(cl.r[c].data(), data.U.rows());
  }
  return identify_closed_loop(data.U, R, data.Y, data.sample_time_min, data.layout, options);
}

// SPEC §6 as the open-loop campaign does it: run a's two-stage model on run b's applied u,
// scored from rest at each segment (a NaN fit makes the model's cross figures NaN), and
// each model's figures over the other runs against the truth's fit on them (none for a
// campaign of one design: its figures stay NaN).
void cross_validate(std::vector<ClosedLoopExperiment>& runs, const std::vector<StackedRuns>& data,
                    int threads) {
  const auto R = static_cast<Eigen::Index>(runs.size());
  parallel_for(static_cast<int>(R), threads, [&](int a) {
    ClosedLoopExperiment& e = runs[static_cast<std::size_t>(a)];
    e.crossfit.resize(R);
    for (Eigen::Index b = 0; b < R; ++b) {
      const StackedRuns& d = data[static_cast<std::size_t>(b)];
      e.crossfit(b) = mean_scored_fit(e.identified.two_stage.model, d.U, d.Y, d.layout);
    }
  });
  if (R < 2) return;
  Eigen::VectorXd truth(R);
  for (Eigen::Index b = 0; b < R; ++b) truth(b) = runs[static_cast<std::size_t>(b)].truth_fit;
  for (Eigen::Index a = 0; a < R; ++a) {
    ClosedLoopExperiment& e = runs[static_cast<std::size_t>(a)];
    e.cross = cross_fit_figures(e.crossfit, truth, a);
  }
}

}  // namespace

ClosedLoopCampaign run_closed_loop_campaign(const ClosedLoopCampaignOptions& o, const fs::path& dir,
                                            const std::function<void(const std::string&)>& say) {
  check_excitation(o.design.excitation);
  const PriorKnowledge prior = case_study(o.plant);
  const std::vector<const PresetInfo*> set = closed_loop_presets(o.designs);  // names first
  const auto plant = sim::make_plant(o.plant);
  const std::vector<std::string> cvs = plant->output_names();
  const sim::control::ControllerFile file = sim::control::load_controller_file(o.controller);
  ClosedLoopDesignOptions design_options = o.design;
  resolve_cv_limits(design_options, file, static_cast<Eigen::Index>(cvs.size()));
  const std::optional<LoopPace> pace = setpoint_pace(design_options, prior, file);
  const PriorKnowledge& designed_on = pace ? pace->prior : prior;
  if (say && pace) say(loop_pace_line(*pace, prior));
  const double noise =
      o.noise_variance >= 0.0 ? o.noise_variance : case_study_noise_variance(o.plant);
  const GainAnalysis true_gain = analyse_gain(plant->static_gain());
  std::vector<ClosedLoopExperiment> out(set.size());
  std::vector<StackedRuns> data(set.size());
  parallel_for(static_cast<int>(set.size()), std::max(1, o.threads), [&](int k) {
    const PresetInfo& preset = *set[static_cast<std::size_t>(k)];
    ClosedLoopExperiment& e = out[static_cast<std::size_t>(k)];
    e.number = preset.number;
    e.name = std::string(preset.acronym);
    const std::string folder = experiment_folder(e.number, e.name);
    const fs::path work = dir / "runs" / folder;
    fs::create_directories(work);
    e.run_log = "runs/" + folder + "/run.csv";
    e.model = "models/" + folder + ".json";
    const Design design = design_closed_loop(design_options, designed_on, preset, cvs, file);
    const fs::path plan_path = work / (e.name + ".plan");
    write_plan_file(*design.plan, plan_path);
    const std::uint64_t seed = o.seed + static_cast<std::uint64_t>(e.number);
    runlog::RunLog log;
    if (o.loop) {
      LoopRun run;
      run.plan = plan_path;
      run.work_dir = work;
      run.config.plant = o.plant;
      run.config.noise_var = noise;
      run.config.seed = seed;
      run.config.controller = fs::absolute(o.controller).string();
      run.config.offsets = o.design.excitation;
      // The gateway's CV setpoint offsets within ± the largest CV test limit; no CV test
      // limits of the gateway's own beyond that.
      if (design_options.excitation == "setpoint") {
        run.config.output_range =
            std::max(design_options.cv_high.maxCoeff(), (-design_options.cv_low).maxCoeff());
      }
      run.programs = o.programs;
      LoopResult streamed = stream_in_the_loop(run);
      log = std::move(streamed.log);
      if (say)
        say(e.name + ": closed loop through excite-gateway to excite-plant --controller, " +
            std::to_string(log.rows()) + " ticks in " +
            std::to_string(streamed.seconds).substr(0, 4) + " s");
    } else {
      write_run_log(run_in_process(o, *design.plan, e.name, noise, seed), dir / e.run_log);
      runlog::ReadResult read =
          runlog::read_run_log((dir / e.run_log).string(), limited_read_options());
      if (!read.ok()) throw std::runtime_error(read.error->to_string());
      log = std::move(read.log);
    }
    e.rows = log.rows();
    e.rows_mv_limited = mv_limited_rows(log);
    const StackedRuns& d = data[static_cast<std::size_t>(k)] = stack_log(log, e.run_log);
    e.identified = identify_log(log, d, e.run_log);
    e.balance = balance_of(scored_about_segment_means(d.Y, d.layout), true_gain);
    e.truth_fit =
        mean_finite(truth_fit(*sim::make_plant(o.plant), d.U, d.Y, d.sample_time_min, d.layout));
    nlohmann::json j = model_json(e.identified.two_stage, log.input_names, log.output_names);
    j["closed_loop"] = closed_loop_json(e.identified, log, false);
    fs::create_directories(dir / "models");
    write_whole_file(dir / e.model, j.dump(2) + "\n");
    if (say)
      say(e.name + ": identified (two-stage), " + e.model + "; rows with an MV limited " +
          std::to_string(e.rows_mv_limited) + " of " + std::to_string(e.rows));
  });
  cross_validate(out, data, o.threads);
  return {designed_on.tau_low_min, pace ? std::optional(pace->speed) : std::nullopt,
          std::move(out)};
}

}  // namespace excite::host
