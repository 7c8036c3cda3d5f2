// SPDX-License-Identifier: MIT
// A Monte Carlo unit with the controller on (work.hpp ClosedLoopConfig; README "With the
// controller on"): the closed-loop designs, prepared once, and a unit's closed-loop
// experiment on the seed's plant under the controller on the seed's model.
#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/config/error.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/montecarlo/unit.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/library/library.hpp"
#include "sim/library/perturb.hpp"

namespace excite::host::montecarlo {

void prepare_closed_loop(Prepared& p, const PriorKnowledge& prior) {
  const ClosedLoopConfig& c = p.config.closed_loop;
  sim::control::ControllerFile file = sim::control::load_controller_file(c.controller);
  if (!file.model.model_file.empty()) {
    throw std::invalid_argument(file.source + ": model.model_file = \"" + file.model.model_file +
                                "\", expected model.plant for a Monte Carlo run");
  }
  if (c.model_perturb_percent > 0.0 && file.kind != sim::control::ControllerKind::dmc) {
    throw std::invalid_argument(
        "--controller-perturb = " + sim::percent_text(c.model_perturb_percent) + " with " +
        file.source +
        ", expected 0 for a PI controller (its model gives only the "
        "sizes and the gains' signs; a DMC predicts with it)");
  }
  if (c.model_perturb_percent > 0.0) {
    const std::vector<std::string> names = sim::library_plant_names();
    if (std::find(names.begin(), names.end(), file.model.plant) == names.end()) {
      throw std::invalid_argument(
          "--controller-perturb = " + sim::percent_text(c.model_perturb_percent) + " with " +
          file.source + "'s model.plant = \"" + file.model.plant +
          "\", expected a linear library plant's name (only its "
          "gains, time constants and delays can be perturbed)");
    }
    p.controller_model = sim::library_plant(file.model.plant);
  }
  // The file against the plant once: sizes, sample time, ranges, and its own model's
  // integral controllability for the nominal plant.
  const Eigen::MatrixXd g0 = sim::make_plant(p.config.plant)->static_gain();
  (void)sim::control::make_controller(file, *sim::control::load_model(file), &g0);
  ClosedLoopDesignOptions design;
  design.excitation = c.excitation;
  design.limit_fraction = c.limit_fraction;
  design.mv_fraction = c.mv_fraction;
  design.directions = c.directions;
  design.prbs_phase = c.prbs_phase;
  const std::vector<std::string> cvs = sim::make_plant(p.config.plant)->output_names();
  resolve_cv_limits(design, file, static_cast<Eigen::Index>(cvs.size()));
  if (design.cv_low.size() > 0) {
    p.cv_low = design.cv_low;
    p.cv_high = design.cv_high;
  } else if (file.dmc.cv.size() == cvs.size()) {  // MV dither under a DMC: its CV limits
    ClosedLoopDesignOptions setpoint = design;
    setpoint.excitation = "setpoint";
    resolve_cv_limits(setpoint, file, static_cast<Eigen::Index>(cvs.size()));
    p.cv_low = setpoint.cv_low;
    p.cv_high = setpoint.cv_high;
  }
  // Setpoint excitation at the loop's pace: (4.2.3)'s τ_L the loop's (closed_loop_designs.hpp).
  design.switching = c.switching;
  const std::optional<LoopPace> pace = setpoint_pace(design, prior, file);
  const PriorKnowledge& designed_on = pace ? pace->prior : prior;
  for (std::size_t d = 0; d < p.presets.size(); ++d)
    p.designs[d] = design_closed_loop(design, designed_on, p.presets[d], cvs, file);
  p.controller = std::move(file);
}

SeedController seed_controller(const Prepared& p, std::uint64_t seed,
                               const Eigen::MatrixXd& plant_gain) {
  const sim::control::ControllerFile& file = *p.controller;
  const std::unique_ptr<sim::Plant> model =
      p.controller_model
          ? sim::make_linear_plant(file.model.plant,
                                   sim::perturbed_plant(*p.controller_model,
                                                        p.config.closed_loop.model_perturb_percent,
                                                        controller_model_seed(seed)))
          : sim::control::load_model(file);
  SeedController out;
  try {
    out.controller = sim::control::make_controller(file, *model, &plant_gain);
  } catch (const config::Error& e) {
    out.refused = e.what();  // prepare_closed_loop made the nominal one: only the draw is wrong
  }
  return out;
}

ClosedLoopRun closed_loop_experiment(const Prepared& p, const Unit& unit, sim::Plant& plant,
                                     sim::control::Controller& controller, const TruePlant& truth) {
  const ClosedLoopConfig& c = p.config.closed_loop;
  const sim::control::ControllerFile& file = *p.controller;
  const auto d = static_cast<std::size_t>(unit.design);
  ClosedLoopExperimentOptions options;
  options.loop.excitation =
      c.excitation == "mv" ? runlog::Excitation::mv : runlog::Excitation::setpoint;
  set_controller(options.loop, file, std::filesystem::path(c.controller).filename().string());
  options.measured.noise_variance = p.config.noise_variance;
  options.measured.seed = kSeedStride * unit.seed + static_cast<std::uint64_t>(p.presets[d].number);
  options.measured.disturbance_std = c.disturbance_std;
  options.measured.disturbance_tau_min = c.disturbance_tau_min;
  options.max_time_constant_min = p.max_time_constant_min;
  options.direct = c.method == "direct";
  return run_closed_loop_experiment(p.designs[d], p.presets[d], plant, controller, options,
                                    truth.gain);
}

}  // namespace excite::host::montecarlo
