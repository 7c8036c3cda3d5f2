// SPDX-License-Identifier: MIT
#include "host/adaptive/recorded_test.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "host/adaptive/cv_limit_text.hpp"
#include "host/adaptive/decision_log.hpp"
#include "host/adaptive/inbox_runner.hpp"
#include "host/adaptive/plant_runner.hpp"
#include "host/adaptive/segments.hpp"
#include "host/adaptive/study.hpp"
#include "host/adaptive/test_folder.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/design/case_studies.hpp"
#include "host/export/model_file.hpp"
#include "host/output/whole_file.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/library/perturb.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

namespace fs = std::filesystem;

namespace {

// The last estimate as DIR/model.json, when there is one.
void write_last_model(const AdaptiveResult& r, const fs::path& dir,
                      const std::vector<std::string>& inputs,
                      const std::vector<std::string>& outputs) {
  if (r.estimates.empty()) return;
  write_whole_file(dir / "model.json",
                   model_json(r.estimates.back().result, inputs, outputs).dump(2) + "\n");
}

// The whole in-process test as one run log.
SimulatedRun whole_run(const sim::Plant& plant, const PriorKnowledge& prior,
                       const AdaptiveResult& r) {
  SimulatedRun run;
  run.plant = plant.name();
  run.plan = "excite test";
  run.producer = "excite test " + std::string(runlog::kVersion);
  run.sample_time_min = r.sample_time_min;
  run.time_scales = {prior.tau_high_min, prior.beta, 0.0};
  run.input_names = plant.input_names();
  run.input_units = plant.input_units();
  run.output_names = plant.output_names();
  run.output_units = plant.output_units();
  run.input_baseline = plant.input_baseline();
  run.du = r.U;
  run.dy = r.Y;
  return run;
}

// What the operator does at the gateway, said when the loop needs it.
InboxHooks operator_prompts(const GatewayTest& t, std::ostream& out) {
  InboxHooks hooks;
  hooks.start = [&t, &out](const plan::Plan&) {
    out << "start the gateway on the first segment: excite-gateway --plan "
        << (t.folder / "segments" / "segment-0.plan").string() << " --segment-inbox " << t.inbox
        << " --log " << t.run_log
        << " (its configuration with [segments] await_s longer than an identification)\n"
        << std::flush;
  };
  hooks.approve = [&t, &out](int k) {
    out << "segment " << k << " is in " << (fs::path(t.inbox) / "next.plan").string()
        << ": approve it at the gateway (stdin approve, command register 5) unless its "
           "[segments] preapproved_from is \"excite test segment\"\n"
        << std::flush;
  };
  hooks.attached = [&t, &out](const std::string& run) {
    out << "gateway run " << run << " (" << (fs::path(t.inbox) / "gateway.run").string()
        << "): reading only its log " << t.run_log << "\n"
        << std::flush;
  };
  return hooks;
}

}  // namespace

void run_simulated_test(const SimulatedTest& t, std::ostream& out) {
  const PriorKnowledge prior = case_study(t.plant);
  sim::check_perturbable(t.plant, t.perturb_percent);
  auto plant = true_plant(t.plant, t.perturb_percent, t.seed);
  AdaptiveOptions adaptive = t.adaptive;
  if (!t.limits.empty()) {
    adaptive.limits = parse_cv_limits(t.limits, plant->output_names(), "the plant's");
  }
  check_adaptive_test(prior, adaptive);
  prepare_test_folder(t.folder, kTestFolderNames);
  const double noise =
      t.noise_variance >= 0.0 ? t.noise_variance : case_study_noise_variance(t.plant);
  PlantRunner runner(*plant, prior.sample_time_min, noise, t.seed);
  FolderLog log(t.folder, plant->input_names(), plant->output_names(), out);
  const AdaptiveResult r = run_adaptive_test(prior, runner, adaptive, &log);

  const SimulatedRun run = whole_run(*plant, prior, r);
  write_run_log(run, t.folder / "run.csv");
  write_last_model(r, t.folder, run.input_names, run.output_names);
  out << "wrote " << (t.folder / "decisions.jsonl").string() << ", status.txt, run.csv"
      << (r.estimates.empty() ? "" : ", model.json") << " and " << r.segments.size()
      << " segment plan(s)\n";
}

// Each segment into the gateway's inbox, the rows read back from its run log (InboxRunner).
// The operator starts the gateway on segment 0 and approves each next one at the gateway,
// unless its configuration pre-approves "excite test segment".
void run_gateway_test(const GatewayTest& t, std::ostream& out) {
  const PriorKnowledge& prior = t.prior;
  std::vector<std::string> inputs, outputs;
  for (const InputSpec& in : prior.inputs) inputs.push_back(in.name);
  for (Eigen::Index j = 0; j < prior.gain.rows(); ++j)
    outputs.push_back("y" + std::to_string(j + 1));
  AdaptiveOptions adaptive = t.adaptive;
  if (!t.limits.empty()) {
    if (outputs.empty()) {
      throw std::invalid_argument(
          "--limit: the prior has no G(0), expected one to name its "
          "outputs (y1, y2, … by row) and size the segments");
    }
    adaptive.limits = parse_cv_limits(t.limits, outputs, "the prior's");
  }
  InboxRunnerOptions runner_options;
  runner_options.inbox = t.inbox;
  runner_options.run_log = t.run_log;
  const double timeout_min =
      t.segment_timeout_min > 0.0
          ? t.segment_timeout_min
          : segment_sources(prior).plain.plan->recipe.samples * prior.sample_time_min;
  runner_options.segment_timeout =
      std::chrono::milliseconds(static_cast<long long>(timeout_min * 60'000.0));
  check_adaptive_test(prior, adaptive);
  prepare_test_folder(t.folder, kTestFolderNames);
  InboxRunner runner(runner_options, operator_prompts(t, out));
  FolderLog log(t.folder, inputs, outputs, out);
  const AdaptiveResult r = run_adaptive_test(prior, runner, adaptive, &log);
  write_last_model(r, t.folder, inputs, outputs);
  out << "the test has stopped; the gateway awaits a segment that will not come: end its "
         "run (stdin abort, or let await_s run out). The record is "
      << t.run_log << "; wrote " << (t.folder / "decisions.jsonl").string() << ", status.txt"
      << (r.estimates.empty() ? "" : ", model.json") << " and " << r.segments.size()
      << " segment plan(s)\n";
}

namespace {

// The controller file's [[cv]] limits, for a closed-loop study given no --limit.
CvLimits controller_cv_limits(const ClosedLoopStudyOptions& c, Eigen::Index outputs) {
  ClosedLoopDesignOptions design;
  resolve_cv_limits(design, sim::control::load_controller_file(c.controller), outputs);
  return {design.cv_low, design.cv_high};
}

}  // namespace

void run_recorded_study(const RecordedStudy& study, std::ostream& out) {
  const PriorKnowledge prior = case_study(study.plant);
  sim::check_perturbable(study.plant, study.perturb_percent);
  StudyOptions s;
  s.plant = study.plant;
  s.seeds = study.seeds;
  s.first_seed = study.first_seed;
  s.threads = study.threads;
  s.noise_variance = study.noise_variance;
  s.perturb_percent = study.perturb_percent;
  s.adaptive = study.adaptive;
  s.closed_loop = study.closed_loop;
  if (!study.limits.empty()) {
    s.adaptive.limits =
        parse_cv_limits(study.limits, sim::make_plant(study.plant)->output_names(), "the plant's");
  } else if (s.closed_loop) {
    s.adaptive.limits = controller_cv_limits(*s.closed_loop, prior.gain.rows());
  }
  check_adaptive_test(prior, s.adaptive);
  prepare_test_folder(study.folder, {"study.json"});
  const StudyResult result = run_study(s);
  nlohmann::json j = study_json(result);
  std::string text = study_text(result);
  if (s.adaptive.limits) {
    // The fixed designs at their designed amplitude on the same plants: do they stay inside?
    const double perturb = s.perturb_percent;
    nlohmann::json fixed = nlohmann::json::array();
    for (const char* design : {"prbsUnc", "prbsSimDir", "prbsDirCorrSim", "msGlmZipm"}) {
      int violated = 0;
      double worst = 0.0;
      for (int i = 0; i < s.seeds; ++i) {
        const double ratio = fixed_design_peak_ratio(s.plant, design, *s.adaptive.limits, perturb,
                                                     s.first_seed + static_cast<std::uint64_t>(i));
        worst = std::max(worst, ratio);
        if (ratio > 1.0) ++violated;
        if (perturb <= 0.0) {  // the same plant for every seed: one simulation says it
          violated *= s.seeds;
          break;
        }
      }
      fixed.push_back({{"design", design}, {"violated_seeds", violated}, {"worst_ratio", worst}});
      text += "  fixed " + std::string(design) + ": leaves the limits in " +
              std::to_string(violated) + " of " + std::to_string(s.seeds) + " seeds (worst peak " +
              std::to_string(worst) + " of the limit)\n";
    }
    j["fixed_designs_limits"] = fixed;
  }
  write_whole_file(study.folder / "study.json", j.dump(1) + "\n");
  out << text << "wrote " << (study.folder / "study.json").string() << '\n';
}

}  // namespace excite::host
