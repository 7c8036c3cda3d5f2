// SPDX-License-Identifier: MIT
#pragma once
// One closed-loop experiment in process (issue 41 §4): the campaign's experiment with the
// controller on. A closed-loop design (closed_loop_designs.hpp) is run on the plant under
// the controller (host/simulate/closed_loop.hpp) twice — noise-free, for the balance, and
// measured, with the noise and the coloured disturbance — and the measured run identified by
// the one method asked for, as `excite identify` identifies a closed-loop run log
// (host/identify/closed_loop.hpp: the prediction-error fit with a noise model, on stage
// 1's û or on u; the cross-check is not made).

#include <Eigen/Core>

#include <cstdint>
#include <string>

#include "host/campaign/campaign.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

struct ClosedLoopRun {
  /// The campaign's experiment: U the applied inputs, Y the measured CVs, Y_clean the
  /// noise-free run's (same r, same controller), identified the two-stage estimate (or the
  /// direct fit: options.direct), fit_avg its fit; balance on both runs along the true output
  /// directions. No cross-fit (0).
  Experiment experiment;
  Eigen::MatrixXd R;                // the test signal r (N × r channels): stage 1's regressor
  std::size_t rows_mv_limited = 0;  // measured rows where an MV sat on its box limit
};

struct ClosedLoopExperimentOptions {
  ClosedLoopOptions loop;              // excitation, the MV box, the controller's label
  SimulationOptions measured;          // noise, its seed, the coloured disturbance
  double max_time_constant_min = 0.0;  // identify's bound β·τ_H (0: identify's own)
  bool direct = false;  // experiment.identified: the direct fit, not the two-stage estimate
};

/// Runs `design` (a closed-loop plan: setpoint or MV dither) on `plant` under `controller`
/// (both reset first by each run) and identifies the measured run. `true_gain`: the plant's
/// G(0) analysis, for the balance. The two-stage estimate's gains and SEs come from the
/// instrumental-variable step (identify_two_stage). Throws what simulate_closed_loop,
/// identify_two_stage and identify() throw.
ClosedLoopRun run_closed_loop_experiment(const Design& design, const PresetInfo& preset,
                                         sim::Plant& plant, sim::control::Controller& controller,
                                         const ClosedLoopExperimentOptions& options,
                                         const GainAnalysis& true_gain);

}  // namespace excite::host
