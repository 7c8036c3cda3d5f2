// SPDX-License-Identifier: MIT
// excite test --plant NAME -o DIR [--seed S] [--noise-var V] [--perturb X] [--segment-min H]
//             [--max-min M] [--limit CV=LOW:HIGH …] [--k-sigma K] [--first-scale S]
//             [--weight-floor F]
//             [--residual-tests] [--colour]
// excite test --plant NAME --seeds N [--seed FIRST] [--threads T] … -o DIR
// excite test --plant NAME | --spec FILE --inbox DIR --run-log FILE [--segment-timeout-min M]
//             … -o OUT
// The adaptive plant test (issue 26 §3–§5, host/adaptive/README.md): on a simulated plant
// in-process, one test with its decision log and operator's view or a study over seeds
// measured against the truth (T90); or through a running excite-gateway (its segment inbox
// and its run log), the same loop on whatever plant the gateway drives.

#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <memory>
#include <stdexcept>

#include "host/adaptive/adaptive_test.hpp"
#include "host/adaptive/decision_log.hpp"
#include "host/adaptive/inbox_runner.hpp"
#include "host/adaptive/plant_runner.hpp"
#include "host/adaptive/segments.hpp"
#include "host/adaptive/study.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/cv_limit_option.hpp"
#include "host/export/model_file.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/spec.hpp"
#include "sim/library/perturb.hpp"
#include "host/output/whole_file.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host::cli {
namespace {

namespace fs = std::filesystem;

struct TestCommandOptions {
  std::string plant;
  std::string spec;  // the prior from a design spec (through a gateway only)
  std::string inbox, run_log;
  double segment_timeout_min = 0.0;  // 0: the plain design's length
  std::string output;
  std::uint64_t seed = 1;
  int seeds = 0;  // > 0: a study
  int threads = 1;
  double noise_variance = -1.0;
  std::string perturb = "0";
  std::vector<std::string> limits;
  AdaptiveOptions adaptive;
};

// Refuses a folder that already holds any of the names a test writes there (nothing is
// overwritten), a link among them too, even one to nothing: no link is followed when
// writing (a planted dangling DIR/decisions.jsonl once made the test create its target
// outside DIR).
void prepare_folder(const fs::path& dir, std::initializer_list<const char*> names) {
  std::error_code ec;
  for (const char* name : names) {
    const fs::file_status st = fs::symlink_status(dir / name, ec);
    if (!fs::exists(st)) continue;
    throw std::invalid_argument(
        dir.string() + ": already holds " + name + (fs::is_symlink(st) ? " (a link)" : "") +
        ", expected a new or empty folder (a test's record is not overwritten, no link is "
        "followed)");
  }
  fs::create_directories(dir);
}
// What a test writes into its folder.
constexpr std::initializer_list<const char*> kTestNames = {"decisions.jsonl", "status.txt",
                                                           "run.csv", "model.json", "segments"};

// Writes each event to DIR/decisions.jsonl as it happens (flushed), the operator's view to
// DIR/status.txt (whole), every segment's plan to DIR/segments/, and prints the view.
class FolderLog final : public AdaptiveObserver {
 public:
  FolderLog(fs::path dir, std::vector<std::string> inputs, std::vector<std::string> outputs)
      : dir_(std::move(dir)), inputs_(std::move(inputs)), outputs_(std::move(outputs)), log_() {
    fs::create_directories(dir_ / "segments");
    log_.open(dir_ / "decisions.jsonl");
    if (!log_) throw std::runtime_error((dir_ / "decisions.jsonl").string() + ": cannot write");
  }

  void decided(const AdaptiveResult& r) override {
    const SegmentDecision& s = r.segments.back();
    write(segment_event(s, r.sample_time_min));
    write_plan_file(s.plan, dir_ / "segments" / ("segment-" + std::to_string(s.index) + ".plan"));
    show(r, true);
  }
  void estimated(const AdaptiveResult& r) override {
    write(estimate_event(r.estimates.back(), static_cast<int>(r.estimates.size()) - 1));
  }
  void stopped(const AdaptiveResult& r) override {
    write(stop_event(r));
    show(r, false);
  }

 private:
  void write(const nlohmann::json& event) {
    log_ << event.dump() << '\n';
    log_.flush();
    if (!log_) throw std::runtime_error((dir_ / "decisions.jsonl").string() + ": write failed");
  }
  void show(const AdaptiveResult& r, bool pending) {
    const std::string view = operator_view(r, inputs_, outputs_, pending);
    write_whole_file(dir_ / "status.txt", view);
    std::cout << view << std::flush;
  }

  fs::path dir_;
  std::vector<std::string> inputs_, outputs_;
  std::ofstream log_;
};

void run_one(const TestCommandOptions& opt, const PriorKnowledge& prior, double perturb) {
  const fs::path dir = opt.output;
  auto plant = true_plant(opt.plant, perturb, opt.seed);
  AdaptiveOptions adaptive = opt.adaptive;
  if (!opt.limits.empty()) {
    adaptive.limits = parse_cv_limits(opt.limits, plant->output_names(), "the plant's");
  }
  check_adaptive_test(prior, adaptive);
  prepare_folder(dir, kTestNames);
  const double noise =
      opt.noise_variance >= 0.0 ? opt.noise_variance : case_study_noise_variance(opt.plant);
  PlantRunner runner(*plant, prior.sample_time_min, noise, opt.seed);
  FolderLog log(dir, plant->input_names(), plant->output_names());
  const AdaptiveResult r = run_adaptive_test(prior, runner, adaptive, &log);

  // The whole test as one run log, and the last model.
  SimulatedRun run;
  run.plant = plant->name();
  run.plan = "excite test";
  run.producer = "excite test " + std::string(runlog::kVersion);
  run.sample_time_min = r.sample_time_min;
  run.time_scales = {prior.tau_high_min, prior.beta, 0.0};
  run.input_names = plant->input_names();
  run.input_units = plant->input_units();
  run.output_names = plant->output_names();
  run.output_units = plant->output_units();
  run.input_baseline = plant->input_baseline();
  run.du = r.U;
  run.dy = r.Y;
  write_run_log(run, dir / "run.csv");
  if (!r.estimates.empty()) {
    write_whole_file(
        dir / "model.json",
        model_json(r.estimates.back().result, run.input_names, run.output_names).dump(2) + "\n");
  }
  std::cout << "wrote " << (dir / "decisions.jsonl").string() << ", status.txt, run.csv"
            << (r.estimates.empty() ? "" : ", model.json") << " and " << r.segments.size()
            << " segment plan(s)\n";
}

// Through a running gateway: each segment into its inbox, the rows read back from its run
// log (InboxRunner). The operator starts the gateway on segment 0 and approves each next one
// at the gateway, unless its configuration pre-approves "excite test segment".
void run_through_gateway(const TestCommandOptions& opt, const PriorKnowledge& prior) {
  const fs::path dir = opt.output;
  std::vector<std::string> inputs, outputs;
  for (const InputSpec& in : prior.inputs) inputs.push_back(in.name);
  for (Eigen::Index j = 0; j < prior.gain.rows(); ++j)
    outputs.push_back("y" + std::to_string(j + 1));
  AdaptiveOptions adaptive = opt.adaptive;
  if (!opt.limits.empty()) {
    if (outputs.empty()) {
      throw std::invalid_argument(
          "--limit: the prior has no G(0), expected one to name its "
          "outputs (y1, y2, … by row) and size the segments");
    }
    adaptive.limits = parse_cv_limits(opt.limits, outputs, "the prior's");
  }
  InboxRunnerOptions runner_options;
  runner_options.inbox = opt.inbox;
  runner_options.run_log = opt.run_log;
  const double timeout_min =
      opt.segment_timeout_min > 0.0
          ? opt.segment_timeout_min
          : segment_sources(prior).plain.plan->recipe.samples * prior.sample_time_min;
  runner_options.segment_timeout =
      std::chrono::milliseconds(static_cast<long long>(timeout_min * 60'000.0));
  InboxHooks hooks;
  hooks.start = [&](const plan::Plan&) {
    std::cout << "start the gateway on the first segment: excite-gateway --plan "
              << (dir / "segments" / "segment-0.plan").string() << " --segment-inbox " << opt.inbox
              << " --log " << opt.run_log
              << " (its configuration with [segments] await_s longer than an identification)\n"
              << std::flush;
  };
  hooks.approve = [&](int k) {
    std::cout << "segment " << k << " is in " << (fs::path(opt.inbox) / "next.plan").string()
              << ": approve it at the gateway (stdin approve, command register 5) unless its "
                 "[segments] preapproved_from is \"excite test segment\"\n"
              << std::flush;
  };
  hooks.attached = [&](const std::string& run) {
    std::cout << "gateway run " << run << " (" << (fs::path(opt.inbox) / "gateway.run").string()
              << "): reading only its log " << opt.run_log << "\n"
              << std::flush;
  };
  check_adaptive_test(prior, adaptive);
  prepare_folder(dir, kTestNames);
  InboxRunner runner(runner_options, hooks);
  FolderLog log(dir, inputs, outputs);
  const AdaptiveResult r = run_adaptive_test(prior, runner, adaptive, &log);
  if (!r.estimates.empty()) {
    write_whole_file(dir / "model.json",
                     model_json(r.estimates.back().result, inputs, outputs).dump(2) + "\n");
  }
  std::cout << "the test has stopped; the gateway awaits a segment that will not come: end its "
               "run (stdin abort, or let await_s run out). The record is "
            << opt.run_log << "; wrote " << (dir / "decisions.jsonl").string() << ", status.txt"
            << (r.estimates.empty() ? "" : ", model.json") << " and " << r.segments.size()
            << " segment plan(s)\n";
}

void run_study_command(const TestCommandOptions& opt, double perturb) {
  const fs::path dir = opt.output;
  StudyOptions s;
  s.plant = opt.plant;
  s.seeds = opt.seeds;
  s.first_seed = opt.seed;
  s.threads = opt.threads;
  s.noise_variance = opt.noise_variance;
  s.perturb_percent = perturb;
  s.adaptive = opt.adaptive;
  if (!opt.limits.empty()) {
    s.adaptive.limits =
        parse_cv_limits(opt.limits, sim::make_plant(opt.plant)->output_names(), "the plant's");
  }
  check_adaptive_test(case_study(opt.plant), s.adaptive);
  prepare_folder(dir, {"study.json"});
  const StudyResult result = run_study(s);
  nlohmann::json j = study_json(result);
  std::string text = study_text(result);
  if (s.adaptive.limits) {
    // The fixed designs at their designed amplitude on the same plants: do they stay inside?
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
  write_whole_file(dir / "study.json", j.dump(1) + "\n");
  std::cout << text << "wrote " << (dir / "study.json").string() << '\n';
}

void run(const TestCommandOptions& opt) {
  // Everything checked before the folder is made.
  if (!opt.inbox.empty()) {
    if (opt.plant.empty() == opt.spec.empty()) {
      throw std::invalid_argument("--plant = \"" + opt.plant + "\" and --spec = \"" + opt.spec +
                                  "\", expected one of them: the prior knowledge of the test");
    }
    const PriorKnowledge prior =
        opt.spec.empty() ? case_study(opt.plant) : load_design_spec(opt.spec).prior;
    run_through_gateway(opt, prior);
    return;
  }
  if (opt.plant.empty()) {
    throw std::invalid_argument(
        "--plant missing, expected the simulated plant (or --inbox and "
        "--run-log to run through a gateway)");
  }
  const double perturb = sim::parse_perturb(opt.perturb);
  const PriorKnowledge prior = case_study(opt.plant);
  sim::check_perturbable(opt.plant, perturb);
  if (opt.seeds > 0) {
    run_study_command(opt, perturb);
  } else {
    run_one(opt, prior, perturb);
  }
}

}  // namespace

void add_test_command(CLI::App& app) {
  auto opt = std::make_shared<TestCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "test",
      "The adaptive plant test, on a simulated plant or through a running gateway: excite, "
      "re-estimate, re-aim along the least certain gain directions, resize for the CV limits, "
      "stop when the model is good enough");
  CLI::Option* plant = cmd->add_option(
      "--plant", opt->plant,
      "the simulated plant, with its case study as the prior knowledge (through a gateway: the "
      "case study only)");
  CLI::Option* spec = cmd->add_option("--spec", opt->spec,
                                      "through a gateway: the prior knowledge from a design spec")
                          ->check(CLI::ExistingFile);
  spec->excludes(plant);
  CLI::Option* inbox =
      cmd->add_option("--inbox", opt->inbox,
                      "run through a running excite-gateway: its --segment-inbox folder")
          ->check(CLI::ExistingDirectory);
  CLI::Option* run_log = cmd->add_option("--run-log", opt->run_log,
                                         "through a gateway: its --log file (read as it grows)");
  inbox->needs(run_log);
  run_log->needs(inbox);
  spec->needs(inbox);
  cmd->add_option("--segment-timeout-min", opt->segment_timeout_min,
                  "through a gateway: the longest wait for one segment's rows, real minutes "
                  "(default: the plain design's length)")
      ->check(finite_positive())
      ->needs(inbox);
  cmd->add_option("-o,--output", opt->output,
                  "the test's folder: decisions.jsonl, status.txt, segments/, run.csv, model.json "
                  "(a study: study.json)")
      ->required();
  // The simulation's options: not through a gateway.
  cmd->add_option("--seed", opt->seed, "the noise seed (a study: the first seed)")
      ->capture_default_str()
      ->excludes(inbox);
  cmd->add_option("--seeds", opt->seeds,
                  "run a study over this many seeds, judged against the truth")
      ->check(CLI::Range(1, 1'000'000))
      ->excludes(inbox);
  cmd->add_option("--threads", opt->threads, "a study's seeds in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 256))
      ->excludes(inbox);
  cmd->add_option("--noise-var", opt->noise_variance,
                  "measurement noise variance per output (default: the case study's)")
      ->check(finite_non_negative())
      ->excludes(inbox);
  cmd->add_option("--perturb", opt->perturb,
                  "percent: the true plant's gains, time constants and delays drawn within +-X % "
                  "from the seed (linear plants); the prior stays nominal")
      ->capture_default_str()
      ->excludes(inbox);
  cmd->add_option("--segment-min", opt->adaptive.segment_min,
                  "re-estimate after every H minutes (default 4 tau_H; whole PRBS bits)")
      ->check(finite_positive());
  cmd->add_option("--max-min", opt->adaptive.max_length_min,
                  "stop here at the latest (default: the plain PRBS design's length)")
      ->check(finite_positive());
  cmd->add_option("--limit", opt->limits,
                  "a CV's test limits as deviations from its baseline: CV=LOW:HIGH (repeat); "
                  "segments are then sized by predictive amplitude control");
  cmd->add_option("--k-sigma", opt->adaptive.scale.k_sigma,
                  "amplitude control's band: prediction +- k sigma")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--first-scale", opt->adaptive.first_scale,
                  "the plain segments' amplitude as a share of the prior's prbsUnc design "
                  "(0 < S <= 1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--weight-floor", opt->adaptive.weight_floor,
                  "no gain direction's weight below this (0 < F <= 1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_flag("--residual-tests", opt->adaptive.rule.residual_tests,
                "stop only when every output's residual tests pass (1 %) too");
  cmd->add_flag("--colour", opt->adaptive.rule.colour,
                "widen the gain intervals by the residuals' long-run variance ratio");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
