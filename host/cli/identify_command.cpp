// SPDX-License-Identifier: MIT
// excite identify RUN.csv [RUN.csv…] [--json] [-o MODEL] [--max-delay MIN]
//                 [--max-time-constant MIN] [--tau-high MIN] [--beta B] [--threads N]
//                 [--keep-flagged] [--warm-up MIN] [--start-warm-up MIN]
//                 [--trend none|offset|linear] [--structure auto|NAME]
//                 [--structures-from MODEL.json]
// Models per output (each element's structure chosen by BIC, or forced by --structure or to
// an earlier model's by --structures-from), fit % (5.5.1), identified G(0) and its directions.
// Several runs are identified together; the logs' flags decide which rows are scored and where
// the model restarts (host/identify/run_layout.hpp); what was excluded is warned on stderr.
// Time constants are bounded above by β·τ_H (SPEC §6; host/design/time_constant_bound.hpp).
// A closed-loop run (run-log v4, its r recorded) is identified by the two-stage method on r
// (host/identify/closed_loop.hpp) with the direct fit beside it as a cross-check; the model
// written is the two-stage one (--method direct: the direct one). One closed-loop run at a time.

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <utility>

#include "firmware/runlog/reader.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/cli/run_layout_text.hpp"
#include "host/cli/time_constant_bound.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/identify/identification_text.hpp"
#include "host/identify/run_layout.hpp"
#include "host/identify/run_log_input.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/output/text_table.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::cli {
namespace {

struct IdentifyCommandOptions {
  std::vector<std::string> run_paths;
  std::string model_path;
  bool json = false;
  TimeConstantBoundOptions bound;
  IdentifyOptions identify;
  FlagRule rule;
  double warm_up_min = -1.0;  // < 0: the delay bound
  std::string trend = "none";
  std::string initial_state = "auto";
  std::string structure = "auto";
  std::string structures_from;  // a model file whose elements' structures are forced
  bool allow_mixed = false;     // pool runs of other plants or units (issue 19)
  std::string method = "auto";  // closed-loop runs: auto (= two-stage), two-stage, direct
  int stage1_lags = 0;          // 0: project_on_reference's default
  double stage1_pole = -1.0;    // negative: choose_stage1_pole
  NoiseModelOptions noise;      // closed-loop runs: the noise model of both fits
};

// The model file's channel limit, before any fit (a 65-input run once took 77 s and wrote a
// model no other command reads).
void check_model_channels(const runlog::RunLog& first, const std::string& path) {
  for (const auto& [kind, count] : {std::pair{"inputs", first.input_names.size()},
                                    std::pair{"outputs", first.output_names.size()}}) {
    if (count > kMaxModelChannels) {
      throw std::invalid_argument(
          path + ": " + kind + " = " + std::to_string(count) + " channels, expected at most " +
          std::to_string(kMaxModelChannels) + " (a model file's limit, host/README.md Limits)");
    }
  }
}

// The identify options the command line and the logs give: trend, initial state (estimated
// when a log starts mid-test), the structures (--structure, --structures-from).
IdentifyOptions identify_options(const IdentifyCommandOptions& opt,
                                 const std::vector<runlog::RunLog>& runs) {
  const runlog::RunLog& first = runs.front();
  IdentifyOptions options = opt.identify;
  options.trend = opt.trend == "offset"   ? Trend::offset
                  : opt.trend == "linear" ? Trend::linear
                                          : Trend::none;
  bool moving_start = false;  // a log whose record starts mid-test (excite import)
  for (const auto& r : runs) moving_start |= !r.start_at_rest;
  options.estimate_initial_state =
      opt.initial_state == "estimate" || (opt.initial_state == "auto" && moving_start);
  if (opt.structure != "auto") options.structure = structure_from_string(opt.structure);
  if (!opt.structures_from.empty()) {
    ModelChannels channels;
    const IdentifiedModel earlier = read_model_file(opt.structures_from, &channels);
    check_same_channels(channels, opt.structures_from, first.input_names, first.output_names,
                        opt.run_paths.front());
    // An element the earlier model did not estimate has no structure of its own: two poles.
    for (const ElementEstimate& e : earlier.elements) {
      options.structures.push_back(e.estimated() ? e.value.structure : Structure::two_poles);
    }
  }
  if (options.estimate_initial_state && opt.initial_state == "auto") {
    std::cerr << "excite: warning: a run log starts mid-test (start_at_rest: no): each "
                 "segment's initial state is estimated (--initial-state zero to turn off)\n";
  }
  return options;
}

// A closed-loop run (v4, alone): both methods on it (closed_loop.hpp); an open-loop run:
// nothing, and --method must be auto or direct.
std::optional<ClosedLoopIdentification> identify_if_closed_loop(
    const IdentifyCommandOptions& opt, const std::vector<runlog::RunLog>& runs,
    const StackedRuns& data, const IdentifyOptions& options) {
  const runlog::RunLog& first = runs.front();
  for (std::size_t r = 0; r < runs.size(); ++r) {
    if (runs[r].closed_loop.closed && runs.size() > 1) {
      throw std::invalid_argument(opt.run_paths[r] + ": a closed-loop run (v4) among " +
                                  std::to_string(runs.size()) +
                                  " runs, expected it alone (its r explains its own u only)");
    }
  }
  if (first.closed_loop.closed) {
    const runlog::ClosedLoopLog& cl = first.closed_loop;
    if (static_cast<std::size_t>(data.U.rows()) != first.rows()) {
      throw std::invalid_argument(opt.run_paths.front() +
                                  ": rows = " + std::to_string(data.U.rows()) +
                                  " after the flag rule, expected " + std::to_string(first.rows()) +
                                  " (every row of a closed-loop run)");
    }
    Eigen::MatrixXd R(data.U.rows(), static_cast<Eigen::Index>(cl.r.size()));
    for (std::size_t c = 0; c < cl.r.size(); ++c) {
      R.col(static_cast<Eigen::Index>(c)) =
          Eigen::Map<const Eigen::VectorXd>(cl.r[c].data(), data.U.rows());
    }
    return identify_closed_loop(data.U, R, data.Y, data.sample_time_min, data.layout, options,
                                opt.stage1_lags, opt.noise, opt.stage1_pole);
  } else if (opt.method != "auto" && opt.method != "direct") {
    throw std::invalid_argument("--method = " + opt.method +
                                ", expected auto or direct for an open-loop run (the two-stage "
                                "method needs the r of a closed-loop run, run-log v4)");
  }
  return std::nullopt;
}

// The two-stage gains' instrumental-variable step (two_stage_uncertainty.hpp): the largest
// |ΔK| in stage 2's SEs, and the range of the SEs after over stage 2's own.
void print_instrument_step(std::ostream& out, const ClosedLoopIdentification& id) {
  if (id.stage1_se_factor.size() == 0) return;
  double largest = 0.0;
  for (Eigen::Index o = 0; o < id.iv_gain_step.rows(); ++o) {
    for (Eigen::Index i = 0; i < id.iv_gain_step.cols(); ++i) {
      const double own =
          id.two_stage.model.element(static_cast<int>(o), static_cast<int>(i)).std_error.gain /
          id.stage1_se_factor(o, i);
      if (std::isfinite(own) && own > 0.0)
        largest = std::max(largest, std::abs(id.iv_gain_step(o, i)) / own);
    }
  }
  out << "two-stage gains finished by an instrumental-variable step on the applied u: |dK| up "
         "to "
      << num(largest, 2) << " of stage 2's SE; SEs " << num(id.stage1_se_factor.minCoeff(), 3)
      << " to " << num(id.stage1_se_factor.maxCoeff(), 3) << " times stage 2's own\n";
}

void run(const IdentifyCommandOptions& opt) {
  // Every input file counts, --structures-from's too (it was once replaced by -o).
  std::vector<std::string> inputs = opt.run_paths;
  if (!opt.structures_from.empty()) inputs.push_back(opt.structures_from);
  check_identify_output(opt.model_path, inputs, opt.json);
  const HumanTextAside aside(opt.model_path);
  const std::vector<runlog::RunLog> runs = read_pooled_logs(opt.run_paths);
  check_pooled_headers(runs, opt.run_paths, opt.allow_mixed);
  check_model_channels(runs.front(), opt.run_paths.front());
  std::vector<const runlog::RunLog*> logs;
  for (const auto& r : runs) logs.push_back(&r);
  FlagRule rule = opt.rule;
  rule.warm_up_min = opt.warm_up_min >= 0.0 ? opt.warm_up_min : opt.identify.max_delay_min;
  const StackedRuns data = stack_runs(logs, opt.run_paths, rule);
  const runlog::RunLog& first = runs.front();

  IdentifyOptions options = identify_options(opt, runs);
  std::vector<RunTimeScales> scales;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    scales.push_back({opt.run_paths[r], runs[r].plant, runs[r].time_scales.tau_high_min,
                      runs[r].time_scales.beta});
  }
  const auto [bound, source] = time_constant_bound(opt.bound, scales);
  options.max_time_constant_min = bound;
  const std::string summary = layout_summary(data.report, runs.size());
  if (needs_warning(data.report)) std::cerr << "excite: warning: " << summary << '\n';
  const std::optional<ClosedLoopIdentification> closed =
      identify_if_closed_loop(opt, runs, data, options);
  const IdentificationResult result =
      closed ? (opt.method == "direct" ? closed->direct : closed->two_stage)
             : identify(data.U, data.Y, data.sample_time_min, data.layout, options);
  nlohmann::json j = model_json(result, first.input_names, first.output_names);
  j["data"] = layout_json(data.report, opt.run_paths);
  if (closed) j["closed_loop"] = closed_loop_json(*closed, first, opt.method == "direct");
  if (!opt.model_path.empty()) write_whole_file(opt.model_path, j.dump(2) + '\n');
  if (opt.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    const double shown =
        bound > 0.0 ? bound : static_cast<double>(data.U.rows()) * data.sample_time_min;
    std::cout << "time constants bounded by " << num(shown) << " min (" << source << ")\n";
    std::cout << "data: " << summary << "\n";
    if (closed) {
      const auto& fit = closed->stage1.fit_percent;
      std::cout << "closed-loop run (" << runlog::to_text(first.closed_loop.excitation)
                << " excitation, controller " << first.closed_loop.controller << "): "
                << (opt.method == "direct" ? "direct fit on the applied u"
                                           : "two-stage estimate on the part of u that r "
                                             "explains")
                << " (stage 1: " << closed->stage1.lags << " Laguerre functions of pole "
                << num(closed->stage1.pole, 3) << " per r channel; u explained by r:";
      for (Eigen::Index i = 0; i < fit.size(); ++i) std::cout << ' ' << num(fit(i), 3) << " %";
      std::cout << ")\n";
      if (opt.method != "direct") print_instrument_step(std::cout, *closed);
      print_noise_orders(std::cout,
                         opt.method == "direct" ? closed->noise_direct : closed->noise_two_stage,
                         first);
    }
    std::cout << '\n';
    print_identification(std::cout, result, first);
    if (closed) print_closed_loop(std::cout, *closed, first, opt.method == "direct");
  }
}

}  // namespace

void add_identify_command(CLI::App& app) {
  auto opt = std::make_shared<IdentifyCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "identify",
      "Fit a gain, two time constants and a delay for every input-output pair from run logs");
  cmd->add_option("runs", opt->run_paths, "run logs (CSV), identified together")
      ->required()
      ->expected(1, 1 << 16);
  cmd->add_option("-o,--output", opt->model_path, "write the model file (JSON)");
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->add_option("--max-delay", opt->identify.max_delay_min, "upper bound of every delay, min")
      ->capture_default_str()
      ->check(
          finite_number(0.0, true, "a finite number of minutes > 0 (0 leaves no delay to fit)"));
  add_time_constant_bound_options(cmd, opt->bound);
  cmd->add_option("--threads", opt->identify.threads, "outputs fitted in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->add_flag(
      "--keep-flagged", opt->rule.keep_flagged,
      "score rows flagged suspended, comm_lost, clamped, stale or bad_value as good data");
  cmd->add_option("--warm-up", opt->warm_up_min,
                  "minutes not scored after a restart inside a run (default: --max-delay)")
      ->check(finite_non_negative());
  cmd->add_option("--start-warm-up", opt->rule.start_warm_up_min,
                  "minutes not scored at each run's start (data not starting at rest)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--trend", opt->trend,
                  "per segment, each output's offset (offset) or offset and slope (linear) "
                  "fitted with the model")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "offset", "linear"}));
  cmd->add_option("--initial-state", opt->initial_state,
                  "each segment's initial state: zero (at rest), estimate (a free response "
                  "fitted with the model), auto (estimate when a log says its start is not at "
                  "rest)")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "estimate", "zero"}));
  cmd->add_flag("--allow-mixed", opt->allow_mixed,
                "identify runs together even when their plant or units differ");
  cmd->add_option("--structure", opt->structure,
                  "every element's structure: auto (chosen per element by BIC), first_order, "
                  "two_poles, two_poles_zero, integrator, underdamped or underdamped_lag_zero")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "first_order", "two_poles", "two_poles_zero", "integrator",
                             "underdamped", "underdamped_lag_zero"}));
  cmd->add_option("--structures-from", opt->structures_from,
                  "each element in the structure it has in this model file (excite identify -o; "
                  "the same inputs and outputs): re-identify a new test with an earlier model's "
                  "structures; an element that model did not estimate gets two poles")
      ->check(CLI::ExistingFile)
      ->excludes("--structure");
  cmd->add_option("--method", opt->method,
                  "a closed-loop run (run-log v4): auto or two-stage (the projection on r, "
                  "host/identify/README.md), or direct (the fit on the applied u); both are "
                  "prediction-error fits with "
                  "an AR or ARMA(1,1) noise model per output (--noise-order); "
                  "the other is printed beside it as a cross-check")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "two-stage", "direct"}));
  cmd->add_option("--noise-order", opt->noise.max_order,
                  "a closed-loop run: the largest order of each output's AR noise model, "
                  "chosen by BIC, against an ARMA(1,1) too (both fits are prediction-error "
                  "fits with it); 0: output error, no noise model (host/identify/README.md)")
      ->capture_default_str()
      ->check(CLI::Range(0, 60));
  cmd->add_option("--noise-refits", opt->noise.refits,
                  "a closed-loop run: rounds of (noise model from the output error, the row "
                  "refitted on the prefiltered data)")
      ->capture_default_str()
      ->check(CLI::Range(1, 10));
  cmd->add_option("--stage1-lags", opt->stage1_lags,
                  "two-stage: Laguerre functions of each r channel in stage 1 (0: min(200, "
                  "max(20, N/(8 m))))")
      ->capture_default_str()
      ->check(CLI::Range(0, 2000));
  cmd->add_option("--stage1-pole", opt->stage1_pole,
                  "two-stage: the Laguerre pole (0: a FIR; default: chosen from u)")
      ->check(CLI::Range(0.0, 0.999));
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
