// SPDX-License-Identifier: MIT
#pragma once
// How fast a closed loop follows its setpoints (issue 41 §2): the time constant that takes
// τ_L's place in (4.2.3) when the test signal r sits on the CV setpoints. r then reaches the
// plant through the loop r → y, and a PRBS that switches faster than the loop can follow
// hardly moves the plant. In an ill-conditioned plant's weakest output direction that loop is
// slow: the controller needs MV moves ∝ 1/σ_n there, and its move and box limits bound them.
// colaA under its DMC follows a switch along the strong direction in 4 min and along the
// weak one in about 80 (the open-loop τ_L is 15 min).

#include <Eigen/Core>

#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

struct ClosedLoopSpeed {
  double time_constant_min = 0.0;  // from the switch to 63 % of the CVs' move along it
  bool reached = false;  // false: 63 % not reached within the hold (time_constant_min = hold)
};

/// One switch of r, as a PRBS switches, on `plant` under `controller` (both reset first),
/// noise-free and with setpoint excitation: r = −step for hold_rows rows from rest, then
/// +step for hold_rows rows. The time from the switch until the CVs' move along it,
/// (y(k) − y(k_s − 1))ᵀ(2 step) / |2 step|², first reaches 0.63, k_s the switch's row. Throws
/// std::invalid_argument for a step that is zero or not finite, hold_rows < 2, and what
/// simulate_closed_loop refuses.
ClosedLoopSpeed closed_loop_speed(const Eigen::VectorXd& step, int hold_rows,
                                  double sample_time_min, sim::Plant& plant,
                                  sim::control::Controller& controller,
                                  const ClosedLoopOptions& loop);

}  // namespace excite::host
