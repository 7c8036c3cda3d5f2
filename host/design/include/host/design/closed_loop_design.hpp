// SPDX-License-Identifier: MIT
#pragma once
// Designs for a test with the controller on (issue 41 §2; /work/shared/CLOSED-LOOP.md).
//
// - Setpoint excitation: the table is r, offsets of the CV setpoints in CV units (plan
//   version 4, excitation = setpoint; one channel per CV). A plain preset (prbsUnc,
//   msGlmSim, …: uncorrelated across CVs) on the CVs, each CV's amplitude a fraction of its
//   test limits, a_c = fraction · min(|low_c|, high_c); or the same signals along the prior's
//   output directions, r(k) = c · W s(k) (G(0) = W Σ Vᵀ, (5.2.1)), c the largest factor that
//   keeps every channel within its a_c. A controller with integral action then makes
//   u ≈ G(0)⁻¹ r = V Σ⁻¹ Wᵀ r — the rotation of the open-loop directional designs (5.2.2),
//   made by the true plant with no prior (CLOSED-LOOP.md, "Why closed loop helps").
// - MV dither: the open-loop preset unchanged (its channels the MVs), marked excitation = mv:
//   added to the controller's output, the controller told of it or not.

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "host/design/presets.hpp"
#include "host/design/prior_knowledge.hpp"

namespace excite::host {

struct SetpointDesignRequest {
  std::vector<std::string> cv_names;  // one per CV (the plan's channel names)
  Eigen::VectorXd cv_low, cv_high;    // CV test limits, deviations: low < 0 < high, finite
  double fraction = 0.5;              // a_c = fraction · min(|low_c|, high_c), 0 < fraction ≤ 1
  bool along_output_directions = false;  // r = c · W s: needs prior.gain
  // The MVs' room (issue 41 §2): the controller's MV limits, deviations (low < 0 < high), one
  // pair per MV; empty: r is sized by the CV limits alone. With them (and prior.gain, CVs ×
  // MVs), r is scaled down until the MV moves it asks for in steady state, u = G(0)⁺ r over the
  // whole table, stay within mv_fraction of each MV's room, min(|low_i|, high_i). A controller
  // with integral action moves the MVs so at low frequency, and an MV driven to its limit
  // clamps: the controller no longer follows r and the test suspends.
  Eigen::VectorXd mv_low, mv_high;
  double mv_fraction = 0.5;  // 0 < mv_fraction ≤ 1: the rest is left for the transients
  // Every PRBS source started this many switching intervals further into its sequence
  // (PrbsSource::shift, modulo the period): another realisation of the same r, sized as any
  // (a Monte Carlo study runs one r for every seed; this measures others). > 0 needs a PRBS
  // preset.
  std::uint32_t prbs_phase = 0;
};

/// A setpoint-excitation design of a plain `preset` (not a directional one: the directions
/// here are the output directions, `along_output_directions`). Throws std::invalid_argument
/// in the one message form: a directional preset, limits missing, not finite or not about
/// 0, a fraction outside (0, 1], more than 8 CVs, output directions or MV limits without a
/// prior G(0) of as many rows as CVs (and, with MV limits, as many columns as MVs), a PRBS
/// phase for a preset without a PRBS.
Design design_setpoint_excitation(const PriorKnowledge& prior, const PresetInfo& preset,
                                  const SetpointDesignRequest& request,
                                  std::uint64_t created_unix_s);

/// The open-loop design of `preset` marked as MV dither (plan version 4, excitation = mv).
Design design_mv_dither(const PriorKnowledge& prior, const PresetInfo& preset,
                        std::uint64_t created_unix_s);

}  // namespace excite::host
