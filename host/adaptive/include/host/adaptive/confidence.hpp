// SPDX-License-Identifier: MIT
#pragma once
// When may an adaptive test stop, and which gain directions does it still need (issue 26 §3)?
//
// The stop rule is the Monte Carlo accuracy criterion (host/measures/accuracy.hpp: every
// principal minor's sign right, σ_n within ±20 %, v_n within 10°) asked of the model itself
// instead of the truth, which a plant test never knows: it holds "with the grades'
// confidence" when, from the identified gains' covariance (gain_uncertainty.hpp, first-order
// propagation),
//   - every principal minor's 95 % interval excludes 0        |m| ≥ z·SE(m),
//   - σ̂_n within 20 % of every σ_n in its 95 % interval      z·SE(σ_n) ≤ σ̂_n·0.2/1.2 = σ̂_n/6
//     (|σ̂_n − σ_n| ≤ 0.2 σ_n at the interval's low end, where it binds; until 2026-12-01
//     the rule asked z·SE ≤ 0.2 σ̂_n, 20 % lenient there),
//   - v_n's 95 % angle lies within 10°                        z·SE∠(v_n) ≤ 10°,
// z = 1.96 (Student's t instead where a noise model's low-frequency level is uncertain,
// below), and the estimate agrees with an earlier one (the latest with a usable
// uncertainty made on at least one settling time β·τ_H less data: two estimates from nearly
// the same record agree whatever they are — woodberry2x2 with 30-min segments stopped 6 of 100
// seeds with a model that missed the criterion when any previous estimate counted, none with
// this):
//   - σ̂_n within the previous one's z·SE, v̂_n within its z·SE∠, every minor's sign the same.
// The covariance assumes every element's structure and optimum are right: a row that fell
// into a wrong optimum has tight intervals around wrong gains (alatiqi4x4 seed 15: σ̂_n
// 0.41 ± 0.04 at 624 min, true 0.1635, after 1.31 ± 0.43 at 208 min). Estimates from nested
// records differ by less than the earlier one's SE when both are right (for efficient
// estimates Var(x̂_k − x̂_{k−1}) = Var x̂_{k−1} − Var x̂_k), so a jump beyond it says one of
// them is wrong; the test waits for the next estimate. Optionally (`residual_tests`) every
// output's residual must also pass the tests that grade its elements (grade.hpp step 2,
// whiteness and independence at 1 %): right for linear plants, never met on a nonlinear
// column with little noise (colaA: the tests fail on every seed at every length while the
// G(0) is within 7 % and 0.2°, 10 seeds). Each interval part is a *need*: its half-width over
// what the criterion allows (σ_n's: σ̂_n/6; a minor's: z·SE/|m|); the rule holds when the
// largest need, `need`, is ≤ 1, the estimate agrees with the earlier one and (when asked) no
// residual test fails.
//
// Where a row was fitted with a noise model (the direct fit and the two-stage estimate's IV
// step, noise_model.hpp) its SEs scale with the model's low-frequency level, which a record of
// few disturbance time constants tells poorly: the stop rule waits for a short SE and so picks
// the records whose level came out low (woodberry2x2 under its PI, a disturbance of τ 20 min,
// 2026-12-01: a third of the stops wrong, σ̂_n 26–61 % high at 261–348 min). Each interval is
// then read with Student's t at the fewest degrees of freedom of any row's level
// (OutputFit::noise_level_dof), the usual answer to a variance estimated on few degrees of
// freedom; the 95 % coverage is kept, and with white noise or a long record t is z.
//
// The need of every direction i, z·SE(σ_i)/(0.2 σ̂_i) or z·SE∠(v_i)/10° (the tolerances as
// stated: a yardstick whose ratios alone count, kept as the segments were measured with it),
// weights the next segment's excitation along v_i (direction_weights). Half-widths shrink
// about as 1/√length for a stationary excitation, so the test is predicted to stop at
// length · need².

#include <Eigen/Core>

#include <optional>
#include <string>

#include "host/identify/identify.hpp"
#include "host/measures/accuracy.hpp"

namespace excite::host {

struct StopRule {
  double sigma_tolerance = kSigmaTolerance;         // of σ_n, relative (accuracy.hpp)
  double angle_tolerance_deg = kAngleToleranceDeg;  // of v_n (accuracy.hpp)
  double z = 1.96;                                  // ±z SE (95 %); t where a level is uncertain
  bool residual_tests = false;                      // every output's residual tests must pass too
  bool colour = false;  // gain covariances inflated for coloured residuals
};

struct Confidence {
  bool gain_identified = false;    // every gain estimated with a covariance; else all NaN
  double z = 0.0;                  // rule.z, or Student's t at noise_level_dof (rule_quantile)
  double noise_level_dof = 0.0;    // the fewest over the outputs (OutputFit); +∞: none fitted
  double sigma_n_need = 0.0;       // z·SE(σ_n) / (σ̂_n · tolerance/(1 + tolerance))
  double angle_need = 0.0;         // z·SE∠(v_n) / angle tolerance
  double minor_need = 0.0;         // max over minors of z·SE(m) / |m|
  double need = 0.0;               // the largest of the three: the rule holds when ≤ 1
  int sign_uncertain_minors = 0;   // minors with |m| < z·SE(m)
  int failed_residual_tests = 0;   // over outputs: whiteness, independence of each input
  bool agrees = false;             // with the earlier estimate (false without one)
  bool has_previous = false;       // there was an earlier estimate to agree with
  Eigen::VectorXd direction_need;  // per direction i: max(σ_i's, v_i's ratio), as above
  bool met = false;                // need ≤ 1, agrees, has_previous, (asked) residuals pass
  std::string missing;             // what keeps the rule from holding, in words; "" when met
};

/// What the stop rule reads of one estimate.
struct GainEvidence {
  const GainAnalysis* gain = nullptr;            // the identified G(0); null: none
  const GainUncertainty* uncertainty = nullptr;  // its uncertainty (inflated for colour,
                                                 // residual_colour.hpp); null: none usable
  const std::vector<OutputFit>* fits = nullptr;  // residual tests, noise levels; null: not read
  std::string unavailable;                       // why gain or uncertainty is null
};

/// The quantile the rule reads an SE with (the noise model's level uncertain: an SE scaled by
/// an estimated level is a Student-t, not a normal, ratio): `z` when `dof` is +∞, else
/// Student's t at `dof` degrees of freedom (at least one: Cauchy's 12.7 for 95 %) with the
/// two-sided coverage of ±z.
double rule_quantile(double z, double dof);

/// The stop rule applied to an estimate, `previous` the earlier one it must agree with
/// (chosen by the caller as above; null: none, and the rule does not hold). Without G(0) or its
/// uncertainty → gain_identified false, not met.
Confidence confidence_of(const GainEvidence& now, const GainEvidence* previous,
                         const StopRule& rule = {});

/// Weights of the directions for the next segment: w_i = max(floor, need_i / max_k need_k),
/// so the least certain direction gets the full amplitude and none less than `floor` (every
/// direction stays excited: the fit needs all inputs to move). All 1 when the needs are not
/// known. Throws std::invalid_argument for floor outside (0, 1].
Eigen::VectorXd direction_weights(const Confidence& confidence, int directions, double floor);

/// The length at which the rule is predicted to hold: length · need² (length when met);
/// nullopt when the needs are not known.
std::optional<double> predicted_stop_min(const Confidence& confidence, double length_min);

}  // namespace excite::host
