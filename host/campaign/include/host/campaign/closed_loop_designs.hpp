// SPDX-License-Identifier: MIT
#pragma once
// The closed-loop designs of a study (issue 41 §2, §4): which presets, and each one's design
// for a test with the controller on. Shared by the campaign with the controller on
// (host/loop/closed_loop_campaign.hpp) and the Monte Carlo run closed loop
// (host/montecarlo): both run the same designs.
//
// The designs are the plain (not directional) presets of Table 6.1: the controller makes the
// rotation (u ≈ G(0)⁻¹ r), so a directional design has no closed-loop form; r itself can be
// put along the prior's output directions (directions = "output"). Setpoint
// excitation sizes r from the CV test limits (and, with mv_fraction > 0, the controller's MV
// room: host/design/closed_loop_design.hpp); MV dither is the open-loop preset marked as such.

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

#include "host/design/presets.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/simulate/closed_loop_speed.hpp"
#include "sim/control/controller_file.hpp"

namespace excite::host {

struct ClosedLoopDesignOptions {
  std::string excitation = "setpoint";  // or "mv"
  /// Setpoint excitation: the CV test limits (deviations, low < 0 < high); empty: the
  /// controller file's ([[cv]] limits of a DMC), else refused (resolve_cv_limits).
  Eigen::VectorXd cv_low, cv_high;
  double limit_fraction = 0.5;  // each CV's amplitude: this share of its test limit
  // Setpoint excitation: r scaled down until the MV moves it asks for in steady state stay
  // within this share of each MV's limits (the controller file's [[mv]] min, max); 0: r is
  // sized by the CV limits alone.
  double mv_fraction = 0.0;
  // Setpoint excitation: "none" (each CV its own signal) or "output" (the same signals along
  // the prior's output directions, r = c·W s: host/design/closed_loop_design.hpp). Under
  // integral action u ≈ V Σ⁻¹ Wᵀ r, so W's last columns spend the MVs' room on the weak
  // input directions.
  std::string directions = "none";
  // Setpoint excitation: (4.2.3)'s τ_L from the loop's speed along the prior's weakest output
  // direction ("loop": at_the_loops_pace) or the plant's, as open loop ("plant").
  std::string switching = "loop";
  // Setpoint excitation: the PRBS started this many switching intervals in
  // (SetpointDesignRequest::prbs_phase); > 0 needs PRBS presets.
  std::uint32_t prbs_phase = 0;
};

/// Throws std::invalid_argument "--excitation = X, expected setpoint or mv" otherwise.
void check_excitation(const std::string& excitation);

/// Throws std::invalid_argument naming --directions unless it is "none" or "output", and
/// "output" only with setpoint excitation (an MV dither is the open-loop preset as it is).
void check_directions(const std::string& directions, const std::string& excitation);

/// Throws std::invalid_argument "--switching = X, expected loop or plant" otherwise.
void check_switching(const std::string& switching);

/// The presets named (acronyms, in the order given), or every plain preset of Table 6.1 when
/// `names` is empty. Throws std::invalid_argument "--designs = NAME, expected a plain preset
/// …" for a directional one, and find_preset's message for an unknown one.
std::vector<const PresetInfo*> closed_loop_presets(const std::vector<std::string>& names);

/// Setpoint excitation given no CV limits: the controller file's [[cv]] limits (one pair per
/// of the `outputs` CVs). Throws std::invalid_argument "--limit = (none), expected …" when the
/// file has none. Nothing changes for MV dither or limits already given.
void resolve_cv_limits(ClosedLoopDesignOptions& options, const sim::control::ControllerFile& file,
                       Eigen::Index outputs);

/// The closed-loop design of `preset` (options resolved: resolve_cv_limits): a setpoint
/// excitation on the CVs `cv_names` (design_setpoint_excitation, the MV room from `file`'s
/// [[mv]] when mv_fraction > 0, along the prior's output directions when directions =
/// "output") or the MV dither (design_mv_dither). Throws check_directions' message and what
/// they throw.
Design design_closed_loop(const ClosedLoopDesignOptions& options, const PriorKnowledge& prior,
                          const PresetInfo& preset, const std::vector<std::string>& cv_names,
                          const sim::control::ControllerFile& file);

/// The largest α ≤ 1 with |G(0)⁻¹ α r| ≤ mv_fraction · min(−mv_low_i, mv_high_i) on every row
/// of r (rows × CVs) and every MV i: r cut for the MVs' room. 1 with mv_fraction 0 or no MV
/// limits (mv_low of another size than G(0)'s columns).
double mv_room_scale(const Eigen::MatrixXd& gain, const Eigen::MatrixXd& r,
                     const Eigen::VectorXd& mv_low, const Eigen::VectorXd& mv_high,
                     double mv_fraction);

/// Setpoint excitation at the loop's pace (host/adaptive/README.md, "The PRBS switches at the
/// loop's pace"). With r on the setpoints a signal reaches the plant through the loop, and
/// along the prior's weakest output direction w_n the loop is slow: the controller needs MV
/// moves ∝ 1/σ_n there, and its move and box limits bound them. The controller of `file` is
/// timed on its own model (closed_loop_speed.hpp) for the switch r along the output
/// directions gives w_n: ±c·w_n, c the largest factor that keeps each CV j within
/// amplitude_j, cut for the MVs' room (mv_room_scale, the file's MV limits); each side held
/// 4 β·τ_H, so that the loop settles before the switch. `prior` comes back with that time as
/// (4.2.3)'s τ_L, within [its τ_L, τ_H] (the design refuses τ_L > τ_H). Throws config::Error
/// for a file whose model cannot be loaded and std::invalid_argument as closed_loop_speed
/// does.
struct LoopPace {
  PriorKnowledge prior;   // τ_L the loop's
  ClosedLoopSpeed speed;  // what the loop gave
};
LoopPace at_the_loops_pace(const PriorKnowledge& prior, const Eigen::VectorXd& amplitude,
                           double mv_fraction, const sim::control::ControllerFile& file);

/// One line on what `pace` took, against the plant's `prior`: "the loop follows a switch of r
/// along the prior's weakest output direction in 94 min (63 %, on the controller's model):
/// tau_L = 50 min (the plant's 12)".
std::string loop_pace_line(const LoopPace& pace, const PriorKnowledge& prior);

/// Each CV's setpoint amplitude: fraction · min(−low_j, high_j), the CV test limits as
/// deviations (host/design/closed_loop_design.hpp sizes r so).
Eigen::VectorXd cv_amplitude(const Eigen::VectorXd& low, const Eigen::VectorXd& high,
                             double fraction);

/// The pace a study's setpoint designs take (options resolved: resolve_cv_limits):
/// at_the_loops_pace for the amplitudes cv_amplitude gives and the options' MV room, or
/// nothing for an MV dither or switching = "plant" (the prior as it is). Throws
/// check_switching's message and what at_the_loops_pace throws.
std::optional<LoopPace> setpoint_pace(const ClosedLoopDesignOptions& options,
                                      const PriorKnowledge& prior,
                                      const sim::control::ControllerFile& file);

}  // namespace excite::host
