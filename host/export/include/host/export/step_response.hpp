// SPDX-License-Identifier: MIT
#pragma once
// The unit-step response of a (6.1.1) element and its uncertainty (SPEC §6). Time in
// minutes; the response is in output units per input unit.

#include <vector>

#include "host/identify/model.hpp"

namespace excite::host {

/// s(t) of K e^{−s T_d} / ((1 + s T_p1)(1 + s T_p2)) in closed form: 0 for t ≤ T_d, else
/// with τ = t − T_d
///   K (1 − (T_p1 e^{−τ/T_p1} − T_p2 e^{−τ/T_p2}) / (T_p1 − T_p2))   (T_p1 ≠ T_p2),
///   K (1 − (1 + τ/T) e^{−τ/T})                                      (T_p1 = T_p2 = T),
///   K (1 − e^{−τ/T_p1}) with one time constant 0, K with both 0.
/// Time constants within 1e-6 relative of each other use the equal-roots form at their mean
/// (the function is symmetric and smooth in them, so the error is O(1e-12) relative).
/// The other structures (element.hpp) by their exact ZOH discretisation at sample time t
/// (a step is held constant, so it is exact).
double step_response(const ElementModel& p, double t_min);

/// Samples after which every estimated element of the model has settled to within 0.1 % of
/// its gain: max over elements of ⌈settling_time_min / T⌉ (element.hpp), at least 1, at most
/// kMaxSettlingSamples (never a wrapped int).
int settling_samples(const IdentifiedModel& model);
inline constexpr int kMaxSettlingSamples = 1 << 30;

/// The element that settles last and its settling time in samples (unbounded, as a double);
/// output and input are -1 when no element is estimated.
struct Settling {
  double samples = 1.0;
  int output = -1, input = -1;
};
Settling slowest_settling(const IdentifiedModel& model);

/// The step response of an estimate at `times_min` with its 1σ band by linearised
/// propagation: σ_s(t)² = g(t)ᵀ C g(t), C the element's parameter covariance
/// (ElementEstimate::covariance, else diag(std_error²)), g = ∂s/∂θ by central differences.
/// Where a projection widens the gain's reported 95 % interval (model.hpp gain_interval_95),
/// the gain's variance in C is widened to reach it (its farther end; the band is symmetric).
/// A parameter on its bound (NaN covariance) counts as known exactly; one the data do not
/// determine (inf) makes the band unknown: `sigma` is inf wherever the response depends on
/// it. The band ignores the covariance between elements of a row (each element's response
/// depends on its own parameters only).
struct StepBand {
  std::vector<double> response;  // s(t), output units per input unit
  std::vector<double> sigma;     // 1σ of s(t)
};
StepBand step_band(const ElementEstimate& estimate, const std::vector<double>& times_min);

}  // namespace excite::host
