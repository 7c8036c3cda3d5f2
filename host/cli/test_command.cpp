// SPDX-License-Identifier: MIT
// excite test --plant NAME -o DIR [--seed S] [--noise-var V] [--perturb X] [--segment-min H]
//             [--max-min M] [--limit CV=LOW:HIGH …] [--k-sigma K] [--first-scale S]
//             [--weight-floor F]
//             [--residual-tests] [--colour]
// excite test --plant NAME --seeds N [--seed FIRST] [--threads T] … -o DIR
// excite test --plant NAME --seeds N --controller FILE [--method direct|two-stage]
//             [--directions none|output] [--limit-fraction F] [--mv-fraction F]
//             [--switching loop|plant] [--prbs-phase K]
//             [--disturbance-std S --disturbance-tau-min T] … -o DIR
// excite test --plant NAME | --spec FILE --inbox DIR --run-log FILE [--segment-timeout-min M]
//             … -o OUT
// The adaptive plant test (issue 26 §3–§5, host/adaptive/README.md): on a simulated plant
// in-process, one test with its decision log and operator's view or a study over seeds
// measured against the truth (T90); or through a running excite-gateway (its segment inbox
// and its run log), the same loop on whatever plant the gateway drives.

#include <iostream>
#include <memory>
#include <stdexcept>

#include "host/adaptive/recorded_test.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/spec.hpp"
#include "sim/library/perturb.hpp"

namespace excite::host::cli {
namespace {

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
  ClosedLoopStudyOptions closed_loop;  // used when closed_loop.controller is given
  std::string method = "direct";
  std::string directions = "none";  // with --controller: segment 0's r
  std::string switching = "loop";   // with --controller: T_sw from the loop or the plant
};

// Options → one call of host/adaptive/recorded_test.hpp, which checks everything before
// the folder is made.
void run(const TestCommandOptions& opt) {
  if (!opt.inbox.empty()) {
    if (opt.plant.empty() == opt.spec.empty()) {
      throw std::invalid_argument("--plant = \"" + opt.plant + "\" and --spec = \"" + opt.spec +
                                  "\", expected one of them: the prior knowledge of the test");
    }
    run_gateway_test(
        {opt.spec.empty() ? case_study(opt.plant) : load_design_spec(opt.spec).prior, opt.output,
         opt.inbox, opt.run_log, opt.segment_timeout_min, opt.limits, opt.adaptive},
        std::cout);
    return;
  }
  if (opt.plant.empty()) {
    throw std::invalid_argument(
        "--plant missing, expected the simulated plant (or --inbox and "
        "--run-log to run through a gateway)");
  }
  const double perturb = sim::parse_perturb(opt.perturb);
  if (!opt.closed_loop.controller.empty() && opt.seeds == 0) {
    throw std::invalid_argument(
        "--seeds = (none) with --controller, expected a study: the test with the controller "
        "on runs in process over seeds (--seeds 1 for one test)");
  }
  if (opt.seeds > 0) {
    std::optional<ClosedLoopStudyOptions> closed_loop;
    if (!opt.closed_loop.controller.empty()) {
      closed_loop = opt.closed_loop;
      closed_loop->two_stage = opt.method == "two-stage";
      closed_loop->prior_directions = opt.directions == "output";
      closed_loop->switch_from_loop = opt.switching == "loop";
    }
    run_recorded_study({opt.plant, opt.output, opt.seed, opt.seeds, opt.threads, opt.noise_variance,
                        perturb, opt.limits, opt.adaptive, closed_loop},
                       std::cout);
  } else {
    run_simulated_test(
        {opt.plant, opt.output, opt.seed, opt.noise_variance, perturb, opt.limits, opt.adaptive},
        std::cout);
  }
}

// Where the test runs: the simulated plant, or a running gateway's inbox and log; and its
// folder. Returns the --inbox option, which the simulation's options exclude.
CLI::Option* add_where_options(CLI::App* cmd, TestCommandOptions& o) {
  CLI::Option* plant = cmd->add_option(
      "--plant", o.plant,
      "the simulated plant, with its case study as the prior knowledge (through a gateway: the "
      "case study only)");
  CLI::Option* spec =
      cmd->add_option("--spec", o.spec, "through a gateway: the prior knowledge from a design spec")
          ->check(CLI::ExistingFile);
  spec->excludes(plant);
  CLI::Option* inbox =
      cmd->add_option("--inbox", o.inbox,
                      "run through a running excite-gateway: its --segment-inbox folder")
          ->check(CLI::ExistingDirectory);
  CLI::Option* run_log = cmd->add_option("--run-log", o.run_log,
                                         "through a gateway: its --log file (read as it grows)");
  inbox->needs(run_log);
  run_log->needs(inbox);
  spec->needs(inbox);
  cmd->add_option("--segment-timeout-min", o.segment_timeout_min,
                  "through a gateway: the longest wait for one segment's rows, real minutes "
                  "(default: the plain design's length)")
      ->check(finite_positive())
      ->needs(inbox);
  cmd->add_option("-o,--output", o.output,
                  "the test's folder: decisions.jsonl, status.txt, segments/, run.csv, model.json "
                  "(a study: study.json)")
      ->required();
  return inbox;
}

// The simulation's options: not through a gateway.
void add_simulation_options(CLI::App* cmd, TestCommandOptions& o, CLI::Option* inbox) {
  cmd->add_option("--seed", o.seed, "the noise seed (a study: the first seed)")
      ->capture_default_str()
      ->excludes(inbox);
  cmd->add_option("--seeds", o.seeds, "run a study over this many seeds, judged against the truth")
      ->check(CLI::Range(1, 1'000'000))
      ->excludes(inbox);
  cmd->add_option("--threads", o.threads, "a study's seeds in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 256))
      ->excludes(inbox);
  cmd->add_option("--noise-var", o.noise_variance,
                  "measurement noise variance per output (default: the case study's)")
      ->check(finite_non_negative())
      ->excludes(inbox);
  cmd->add_option("--perturb", o.perturb,
                  "percent: the true plant's gains, time constants and delays drawn within +-X % "
                  "from the seed (linear plants); the prior stays nominal")
      ->capture_default_str()
      ->excludes(inbox);
}

// The adaptive test's own options: segments, stop, amplitude control, the rule.
void add_adaptive_options(CLI::App* cmd, TestCommandOptions& o) {
  cmd->add_option("--segment-min", o.adaptive.segment_min,
                  "re-estimate after every H minutes (default 4 tau_H; whole PRBS bits)")
      ->check(finite_positive());
  cmd->add_option("--max-min", o.adaptive.max_length_min,
                  "stop here at the latest (default: the plain PRBS design's length)")
      ->check(finite_positive());
  cmd->add_option("--limit", o.limits,
                  "a CV's test limits as deviations from its baseline: CV=LOW:HIGH (repeat); "
                  "segments are then sized by predictive amplitude control");
  cmd->add_option("--k-sigma", o.adaptive.scale.k_sigma,
                  "amplitude control's band: prediction +- k sigma")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--first-scale", o.adaptive.first_scale,
                  "the plain segments' amplitude as a share of the prior's prbsUnc design "
                  "(0 < S <= 1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--weight-floor", o.adaptive.weight_floor,
                  "no gain direction's weight below this (0 < F <= 1)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_flag("--residual-tests", o.adaptive.rule.residual_tests,
                "stop only when every output's residual tests pass (1 %) too");
  cmd->add_flag("--colour", o.adaptive.rule.colour,
                "widen the gain intervals by the residuals' long-run variance ratio");
}

// With the controller on (issue 41 §4; host/adaptive/README.md): a study only, in process.
void add_closed_loop_options(CLI::App* cmd, TestCommandOptions& o, CLI::Option* inbox) {
  ClosedLoopStudyOptions& c = o.closed_loop;
  CLI::Option* controller =
      cmd->add_option("--controller", c.controller,
                      "a study with the controller on: each segment's r on the CV setpoints of "
                      "this controller file's controller (needs --seeds; the CV limits default "
                      "to a DMC file's)")
          ->check(CLI::ExistingFile)
          ->excludes(inbox);
  const auto needs = [&](CLI::Option* option) { option->needs(controller); };
  needs(cmd->add_option("--method", o.method,
                        "with --controller: the estimate, direct (the prediction-error fit with "
                        "its noise model on the applied u) or two-stage")
            ->capture_default_str()
            ->check(CLI::IsMember({"direct", "two-stage"})));
  needs(cmd->add_option("--directions", o.directions,
                        "with --controller: the first segment's r, none (each CV its own PRBS) "
                        "or output (along the prior's output directions); later segments follow "
                        "the estimate's")
            ->capture_default_str()
            ->check(CLI::IsMember({"none", "output"})));
  needs(cmd->add_option("--limit-fraction", c.limit_fraction,
                        "with --controller: r's amplitude as a share of each CV's test limit")
            ->capture_default_str()
            ->check(CLI::Range(1e-6, 1.0)));
  needs(cmd->add_option("--mv-fraction", c.mv_fraction,
                        "with --controller: r cut until the latest estimate's G(0)^-1 r stays "
                        "within this share of the MVs' limits (0: not cut)")
            ->capture_default_str()
            ->check(finite_non_negative()));
  needs(cmd->add_option("--switching", o.switching,
                        "with --controller: the PRBS's switching time by (4.2.3) from the loop's "
                        "speed along the prior's weakest output direction (loop) or from the "
                        "plant's tau_L, as open loop (plant)")
            ->capture_default_str()
            ->check(CLI::IsMember({"loop", "plant"})));
  needs(cmd->add_option("--prbs-phase", c.prbs_phase,
                        "with --controller: start the PRBS this many switching intervals in (every "
                        "seed gets the same r; another phase is another r of the same spectrum)")
            ->capture_default_str()
            ->check(CLI::Range(0, 1'000'000)));
  needs(cmd->add_option("--disturbance-std", c.disturbance_std,
                        "with --controller: a coloured output disturbance of this std")
            ->check(finite_non_negative()));
  needs(cmd->add_option("--disturbance-tau-min", c.disturbance_tau_min,
                        "with --controller: the disturbance's time constant, min")
            ->check(finite_non_negative()));
}

}  // namespace

void add_test_command(CLI::App& app) {
  auto opt = std::make_shared<TestCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "test",
      "The adaptive plant test, on a simulated plant or through a running gateway: excite, "
      "re-estimate, re-aim along the least certain gain directions, resize for the CV limits, "
      "stop when the model is good enough");
  CLI::Option* inbox = add_where_options(cmd, *opt);
  add_simulation_options(cmd, *opt, inbox);
  add_adaptive_options(cmd, *opt);
  add_closed_loop_options(cmd, *opt, inbox);
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
