// SPDX-License-Identifier: MIT
// excite design --plant NAME --preset ACRONYM -o PLAN   (case-study prior knowledge)
// excite design SPEC.toml -o PLAN                       (prior knowledge from a spec)
// excite design --plant NAME --preset ACRONYM --excitation setpoint --limit CV=LO:HI ...
//               [--controller FILE] -o PLAN  (closed loop: r on the CV setpoints)

#include <cstdlib>
#include <ctime>
#include <iostream>
#include <optional>
#include <stdexcept>

#include "host/adaptive/cv_limit_text.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/creation_time.hpp"
#include "host/cli/output_target.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/closed_loop_design.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"
#include "host/design/spec.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host::cli {
namespace {

struct DesignOptions {
  std::string spec;
  std::string plant;
  std::string preset;
  std::string output;
  bool quiet = false;
  std::string excitation = "open";     // open | setpoint | mv (issue 41 §2)
  std::vector<std::string> limits;     // setpoint: CV test limits CV=LOW:HIGH, every CV
  double limit_fraction = 0.5;         // setpoint amplitude = fraction x the test limit
  std::string directions = "none";     // setpoint: none | output
  std::vector<std::string> mv_limits;  // setpoint: the controller's MV limits MV=LOW:HIGH
  double mv_fraction = 0.5;            // setpoint with --mv-limit: r within this share of them
  std::string controller;              // setpoint: (4.2.3)'s τ_L from this controller file's loop
};

// Setpoint excitation: the CVs' test limits (--limit, else a DMC controller file's [[cv]]
// limits) and, with --mv-limit, the MVs' room.
SetpointDesignRequest setpoint_request(const DesignOptions& opt,
                                       const sim::control::ControllerFile* controller) {
  const auto plant = sim::make_plant(opt.plant);
  SetpointDesignRequest request;
  request.cv_names = plant->output_names();
  if (opt.limits.empty() && controller != nullptr) {
    ClosedLoopDesignOptions from_file;
    resolve_cv_limits(from_file, *controller, static_cast<Eigen::Index>(request.cv_names.size()));
    request.cv_low = from_file.cv_low;
    request.cv_high = from_file.cv_high;
  } else {
    const CvLimits limits = parse_cv_limits(opt.limits, request.cv_names, "the plant's");
    request.cv_low = limits.low;
    request.cv_high = limits.high;
  }
  request.fraction = opt.limit_fraction;
  request.along_output_directions = opt.directions == "output";
  if (!opt.mv_limits.empty()) {
    const CvLimits mvs = parse_mv_limits(opt.mv_limits, plant->input_names(), "the plant's");
    request.mv_low = mvs.low;
    request.mv_high = mvs.high;
    request.mv_fraction = opt.mv_fraction;
  }
  return request;
}

// Setpoint excitation with --controller: (4.2.3)'s τ_L the loop's (at_the_loops_pace,
// host/campaign/closed_loop_designs.hpp), timed for the request's CV amplitudes and, with
// --mv-limit, its MV room under the controller's own MV limits. Says what it took.
PriorKnowledge at_the_controllers_pace(const DesignOptions& opt, const PriorKnowledge& prior,
                                       const SetpointDesignRequest& request,
                                       const sim::control::ControllerFile& controller) {
  const LoopPace pace =
      at_the_loops_pace(prior, cv_amplitude(request.cv_low, request.cv_high, request.fraction),
                        opt.mv_limits.empty() ? 0.0 : opt.mv_fraction, controller);
  if (!opt.quiet) std::cout << loop_pace_line(pace, prior) << '\n';
  return pace.prior;
}

void run(const DesignOptions& opt) {
  refuse_output_among_inputs(opt.output, {opt.spec});
  const HumanTextAside aside(opt.output);
  PriorKnowledge prior;
  std::string preset_name;
  Design design;
  if (!opt.spec.empty()) {
    if (!opt.plant.empty() || !opt.preset.empty()) {
      throw std::invalid_argument("give either SPEC.toml or --plant with --preset, not both");
    }
    DesignSpec spec = load_design_spec(opt.spec);
    prior = std::move(spec.prior);
    preset_name = spec.design;
    if (spec.multisine) design = design_plain_multisine(prior, *spec.multisine, creation_time());
  } else {
    if (opt.plant.empty() || opt.preset.empty()) {
      throw std::invalid_argument("give SPEC.toml, or --plant NAME with --preset ACRONYM");
    }
    prior = case_study(opt.plant);
    preset_name = opt.preset;
  }
  if (opt.excitation == "mv" && !opt.mv_limits.empty()) {
    throw std::invalid_argument(
        "--mv-limit with --excitation = mv, expected --excitation "
        "setpoint (it sizes r by the MVs' room)");
  }
  if (!opt.controller.empty() && opt.excitation != "setpoint") {
    throw std::invalid_argument("--controller with --excitation = " + opt.excitation +
                                ", expected --excitation setpoint (it times the loop r goes "
                                "through)");
  }
  if (opt.excitation != "open") {
    if (opt.plant.empty() || design.plan) {
      throw std::invalid_argument("--excitation = " + opt.excitation +
                                  " with a spec file, expected --plant NAME --preset ACRONYM");
    }
    const PresetInfo& preset = find_preset(preset_name);
    if (opt.excitation == "mv") {
      design = design_mv_dither(prior, preset, creation_time());
    } else {
      std::optional<sim::control::ControllerFile> controller;
      if (!opt.controller.empty()) controller = sim::control::load_controller_file(opt.controller);
      const SetpointDesignRequest request =
          setpoint_request(opt, controller ? &*controller : nullptr);
      if (controller) prior = at_the_controllers_pace(opt, prior, request, *controller);
      design = design_setpoint_excitation(prior, preset, request, creation_time());
    }
  } else if (!opt.limits.empty() || opt.directions != "none" || !opt.mv_limits.empty()) {
    throw std::invalid_argument(
        "--limit/--directions/--mv-limit with --excitation = open, expected "
        "--excitation setpoint (they size and turn the CV setpoints)");
  }
  if (!design.plan) design = design_preset(prior, find_preset(preset_name), creation_time());
  write_plan_file(*design.plan, opt.output);
  if (design.limit_scale < 1.0 - 1e-9) {  // said even with --quiet: the size changed
    std::cerr << "note: the design does not fit the input limits; the whole design is scaled by "
              << design.limit_scale << " (directions preserved, no channel clipped)\n";
  }
  if (!opt.quiet) {
    for (const std::string& note : design.notes) std::cout << note << '\n';
    std::cout << "wrote " << opt.output << ": " << preset_name << ", "
              << design.plan->recipe.channels << " channels x " << design.plan->recipe.samples
              << " samples\n";
  }
}

}  // namespace

void add_design_command(CLI::App& app) {
  auto opt = std::make_shared<DesignOptions>();
  CLI::App* cmd = app.add_subcommand("design", "Design an experiment and write its plan file");
  cmd->add_option("spec", opt->spec, "design spec (TOML); see host/README.md")
      ->check(CLI::ExistingFile);
  cmd->add_option("--plant", opt->plant, "library plant whose case-study prior knowledge to use");
  cmd->add_option(
      "--preset", opt->preset,
      "a named design, e.g. prbsSimDir (steps, PRBS or multisines; host/README.md lists them)");
  cmd->add_option("-o,--output", opt->output, "plan file to write")->required();
  cmd->add_flag("-q,--quiet", opt->quiet, "print nothing on success");
  cmd->add_option("--excitation", opt->excitation,
                  "open (the MVs, open loop), setpoint (closed loop: the table is r on the CV "
                  "setpoints, in CV units; needs --limit for every CV, or --controller with a DMC "
                  "file's [[cv]] limits) or mv (closed loop: a "
                  "dither on the controller's MV output); plan version 4 for the closed loop")
      ->capture_default_str()
      ->check(CLI::IsMember({"open", "setpoint", "mv"}));
  cmd->add_option("--limit", opt->limits,
                  "setpoint excitation: CV test limits CV=LOW:HIGH (deviations), every CV; "
                  "amplitude = --limit-fraction x min(|LOW|, HIGH) (default with --controller: "
                  "the DMC file's [[cv]] limits)");
  cmd->add_option("--limit-fraction", opt->limit_fraction,
                  "setpoint excitation: the amplitude's share of each CV's test limit")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--directions", opt->directions,
                  "setpoint excitation: none (uncorrelated across CVs) or output (along the "
                  "prior's output directions W of G(0) = W Sigma V')")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "output"}));
  cmd->add_option("--mv-limit", opt->mv_limits,
                  "setpoint excitation: the controller's MV limits MV=LOW:HIGH (deviations); r "
                  "is scaled down until its steady-state MV moves G(0)^-1 r stay within "
                  "--mv-fraction of them");
  cmd->add_option("--mv-fraction", opt->mv_fraction,
                  "setpoint excitation with --mv-limit: the share of each MV's room r may use")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1.0));
  cmd->add_option("--controller", opt->controller,
                  "setpoint excitation: the controller file (sim/control/README.md) whose loop "
                  "r goes through; (4.2.3)'s tau_L is then the time the controller, on its own "
                  "model, takes to follow a switch of r along the prior's weakest output "
                  "direction (within the plant's tau_L and tau_H), not the plant's tau_L")
      ->check(CLI::ExistingFile);
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
