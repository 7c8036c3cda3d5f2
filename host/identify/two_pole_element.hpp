// SPDX-License-Identifier: MIT
#pragma once
// The identification model element (thesis 6.1.1, SPEC §6)
//
//   G(s) = K e^{−s T_d} / ((1 + s T_p1)(1 + s T_p2)),   T_d ≥ 0, T_p1, T_p2 ≥ 0 (minutes)
//
// and its exact zero-order-hold discretisation with a fractional delay.
//
// PROVISIONAL (for the lead to unify): the project's discretisation belongs in sim/lti
// (excite_sim_lti). When this was written sim/lti had no element discretisation yet, so
// this file implements the one identification needs, self-contained; replace its use by
// the sim/lti single-element API once that exists, keeping tests/unit/host_identify/
// two_pole_element_test.cpp as the oracle both must pass.
//
// Discretisation. With sample time T and a ZOH input u(k) held on [kT, (k+1)T), the output
// samples y(k) = y(kT) of G obey exactly
//
//   y(k) = −a1 y(k−1) − a2 y(k−2) + Σ_{j=0..3} b_j u(k − d − j),   d = ⌊T_d / T⌋,
//
// with a1 = −(φ1 + φ2), a2 = φ1 φ2, φ_i = e^{−T/T_pi} (0 when T_pi = 0), and
// b_j = h(d+j) + a1 h(d+j−1) + a2 h(d+j−2), where h(m) = S(mT − T_d) − S((m−1)T − T_d) is
// the ZOH pulse response and S the continuous step response (S(t) = 0 for t < 0). The
// pulse response obeys the recursion from m = d + 4 on, so four numerator taps suffice.
// S is evaluated in a form that is exact and well conditioned for T_p1 = T_p2 (double
// pole), T_p1 ≈ T_p2, and T_p → 0 (a first-order element, or a pure gain with delay,
// for which S(0) = K: a pure gain passes u(k − d) at θ = 0).

#include <array>
#include <cstddef>
#include <span>

namespace excite::host {

/// One element of (6.1.1). Units: minutes; gain in output unit per input unit.
struct TwoPoleDelay {
  double gain = 0.0;       // K
  double delay_min = 0.0;  // T_d
  double tp1_min = 0.0;    // T_p1
  double tp2_min = 0.0;    // T_p2
};

/// Continuous step response of the element at time t (minutes after the step).
double step_response(const TwoPoleDelay& g, double t_min);

/// y(k) = −a1 y(k−1) − a2 y(k−2) + Σ_j b[j] u(k − delay_samples − j).
struct DiscreteTwoPole {
  double a1 = 0.0;
  double a2 = 0.0;
  std::array<double, 4> b{};
  std::size_t delay_samples = 0;  // d = ⌊T_d / T⌋
};

/// Exact ZOH discretisation at sample time T (minutes). Preconditions (checked by callers
/// on user input): T > 0, T_d ≥ 0, T_p1, T_p2 ≥ 0, all finite.
DiscreteTwoPole discretise(const TwoPoleDelay& g, double sample_time_min);

/// Denominator {a1, a2} = {−(φ1 + φ2), φ1 φ2}, φ_i = e^{−T/T_pi} (0 when T_pi = 0).
std::array<double, 2> denominator(const TwoPoleDelay& g, double sample_time_min);

/// Numerator tap b̃_m = h(m) + a1 h(m−1) + a2 h(m−2) for any m ≥ 0, with a1, a2 of g: the
/// coefficient of u(k − m). Zero outside m = d … d+3; used to differentiate the taps
/// across a change of d.
double numerator_tap(const TwoPoleDelay& g, double sample_time_min, double a1, double a2,
                     std::size_t m);

/// y = (G u), k = 0 … N−1, from rest (u(k) = y(k) = 0 for k < 0). u.size() == y.size().
void simulate(const DiscreteTwoPole& g, std::span<const double> u, std::span<double> y);

/// In place x ← x / (1 + a1 q⁻¹ + a2 q⁻²), from rest: x(k) −= a1 x(k−1) + a2 x(k−2).
void all_pole_filter(double a1, double a2, std::span<double> x);

}  // namespace excite::host
