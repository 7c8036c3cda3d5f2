// SPDX-License-Identifier: MIT
#pragma once
// The identification model element (thesis 6.1.1, SPEC §6)
//
//   G(s) = K e^{−s T_d} / ((1 + s T_p1)(1 + s T_p2)),   T_d ≥ 0, T_p1, T_p2 ≥ 0 (minutes),
//
// simulated exactly under zero-order hold, fractional delays included, by THE SAME code as
// the plants: sim/lti's discretise_sopdt / simulate_term (see sim/lti/README.md). This
// header adds what identification needs on top: a guard for vanishing time constants,
// the taps by lag (to differentiate them across a change of the whole-sample delay), and
// the all-pole filter of the sensitivity equations.

#include <array>
#include <cstddef>
#include <span>

#include "sim/lti/sopdt.hpp"

namespace excite::host {

/// One element of (6.1.1): gain K, delay_min T_d, tau1_min T_p1, tau2_min T_p2.
using TwoPoleDelay = sim::SopdtParameters;

/// Time constants below this fraction of T are treated as exactly zero (the first-order or
/// static limit, which the element reaches continuously): the change in the response is
/// below ~1e-7 relative, and sim/lti's realisation loses accuracy for T_p ≪ T.
inline constexpr double kVanishingTimeConstant = 1e-7;

/// Exact ZOH discretisation at sample time T (minutes) via sim::discretise_sopdt, with time
/// constants below kVanishingTimeConstant·T set to 0. Throws std::invalid_argument for
/// negative or non-finite parameters.
sim::DiscreteTerm discretise(const TwoPoleDelay& g, double sample_time_min);

/// y = G u for k = 0 … N−1 from rest; u.size() == y.size().
void simulate(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y);

/// The element as y(k) = −a1 y(k−1) − a2 y(k−2) + Σ_m b_m u(k − m) with the taps b_m listed
/// for lags m = first_lag … first_lag + kLagWindow − 1 (zero where the element has none).
inline constexpr std::size_t kLagWindow = 6;
struct LagTaps {
  double a1 = 0.0;
  double a2 = 0.0;
  std::array<double, kLagWindow> b{};
};
/// Precondition: the element's taps lie inside the window (its whole-sample delay d and the
/// up to three further taps satisfy first_lag ≤ d and d + 3 < first_lag + kLagWindow).
LagTaps lag_taps(const TwoPoleDelay& g, double sample_time_min, std::size_t first_lag);

/// In place x ← x / (1 + a1 q⁻¹ + a2 q⁻²), from rest: x(k) −= a1 x(k−1) + a2 x(k−2).
void all_pole_filter(double a1, double a2, std::span<double> x);

}  // namespace excite::host
