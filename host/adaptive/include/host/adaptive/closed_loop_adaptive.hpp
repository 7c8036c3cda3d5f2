// SPDX-License-Identifier: MIT
#pragma once
// The adaptive test with the controller on (issue 41 §4): the loop of adaptive_test.hpp with
// its segments superimposed on the CV setpoints of a running controller, in process.
//
//   segment 0   plain: r_j = a_j s_j, each CV its own PRBS source s_j (the prior's prbsUnc
//               sources, ±1), a_j = limit_fraction · min(−low_j, high_j) of its test limits;
//               with prior_directions, r = diag(a) D W s instead: W the output directions
//               of the prior's G(0), equal weights, D as in 3 below (every segment before
//               an estimate is usable);
//   after each segment, once the record is long enough to identify:
//     1. identify from all data so far: the prediction-error fit with a noise model per
//        output on the applied u (the direct method, noise_model.hpp: consistent and
//        calibrated under feedback), or two-stage on r;
//     2. the stop rule of confidence.hpp, unchanged (the accuracy criterion at 95 %
//        confidence, agreeing with the estimate a settling time earlier);
//     3. the next segment re-aimed in CV space: r = diag(a) D Ŵ diag(w) s, Ŵ the output
//        directions of the identified G(0), direction i weighted by its need (w_i, the floor
//        as open loop) and D scaling each CV's row so that its peak |r_j| is a_j. The
//        controller turns r along ŵ_i into u ≈ v̂_i σ̂_i⁻¹ |r|: the thesis's V Σ⁻¹ made by the
//        true plant, with the weakest direction the most excited;
//   stop at the maximum length otherwise.
// The MVs' room: when the controller file gives MV limits (a DMC's [[mv]] box) and
// mv_fraction > 0, each segment's r is cut (never raised) until its steady-state moves
// Ĝ(0)⁻¹ r stay within mv_fraction of every MV's limits — Ĝ(0) the latest usable estimate's,
// the prior's before one (closed_loop_design.hpp does the same once, with the prior).
// The sources' switching time is (4.2.3)'s from the prior's τ_L; a study with the controller
// on puts the loop's time constant there (at_the_loops_pace, host/campaign
// closed_loop_designs.hpp; study.hpp), and prbs_phase starts them further into the PRBS.
// The CV limits are not enforced by amplitude control: the controller holds each CV near its
// setpoint, r_j ≤ a_j; the rows outside are counted.

#include <Eigen/Core>

#include <cstdint>

#include "host/adaptive/adaptive_test.hpp"
#include "host/simulate/closed_loop.hpp"
#include "sim/control/controller.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

struct ClosedLoopAdaptiveOptions {
  AdaptiveOptions adaptive;       // segment_min, max_length_min, rule, weight_floor, identify;
                                  // limits: the CV test limits r is sized by (required)
  double limit_fraction = 0.5;    // a_j: this share of each CV's test limit, in (0, 1]
  double mv_fraction = 1.0;       // ≥ 0; 0: r not cut for the MVs' room
  bool two_stage = false;         // the estimate: direct (false) or two-stage
  bool prior_directions = false;  // segment 0 along the prior's output directions (above)
  // The sources start this many switching intervals into the PRBS. Every seed of a study
  // gets the same r; another phase is another r with the same spectrum.
  std::uint64_t prbs_phase = 0;
};

/// The plant under its controller, with the measurement noise and the coloured disturbance
/// of `noise`. run(r) simulates the whole record r from rest: the noise is drawn row by row
/// from the seed, so a longer r continues a shorter one exactly.
class ClosedLoopPlant {
 public:
  ClosedLoopPlant(sim::Plant& plant, sim::control::Controller& controller, ClosedLoopOptions loop,
                  SimulationOptions noise, double sample_time_min);
  /// The run of r (N × outputs, setpoint offsets); noise_free: without noise or disturbance.
  SimulatedRun run(const Eigen::MatrixXd& r, bool noise_free = false);
  const ClosedLoopOptions& loop() const { return loop_; }

 private:
  sim::Plant& plant_;
  sim::control::Controller& controller_;
  ClosedLoopOptions loop_;
  SimulationOptions noise_;
  double sample_time_min_;
};

/// Runs the closed-loop adaptive test (above) from validated prior knowledge of a square
/// plant. The result is run_adaptive_test's: each segment decided (its r in `plan`'s place is
/// not kept: `plan` is empty), each re-estimate, why it stopped, U (applied), Y (measured),
/// Y_true (the same r noise-free), the rows outside the CV limits. Throws
/// std::invalid_argument for options refused by name (no CV limits, a fraction out of range,
/// a plant not square).
AdaptiveResult run_closed_loop_adaptive_test(const PriorKnowledge& prior, ClosedLoopPlant& loop,
                                             const ClosedLoopAdaptiveOptions& options);

}  // namespace excite::host
