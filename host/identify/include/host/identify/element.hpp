// SPDX-License-Identifier: MIT
#pragma once
// The identification model element (thesis 6.1.1, SPEC §6) and the structures beyond it
// (issue 18 §5), time in minutes:
//
//   first_order            K e^{−s Td} / (1 + s T1)
//   two_poles              K e^{−s Td} / ((1 + s T1)(1 + s T2))               — (6.1.1)
//   two_poles_zero         K (1 + s Tz) e^{−s Td} / ((1 + s T1)(1 + s T2))    — Tz > 0 lead/lag,
//                                                                               Tz < 0 inverse
//                                                                               response
//   integrator             K e^{−s Td} / (s (1 + s T1))                       — K per minute
//   underdamped            K e^{−s Td} / (Tn² s² + 2ζ Tn s + 1)                — 0 < ζ ≤ 1
//   underdamped_lag_zero   K (1 + s Tz) e^{−s Td} / ((1 + s T1)(Tn² s² + 2ζ Tn s + 1))
//
// Td, T1, T2, Tn ≥ 0. Every structure is one formula with some parameters held fixed (Tz = 0,
// T2 = 0, Tn = 0, ζ = 1 where a structure has none), so one parameter vector serves them all.
// Each is simulated exactly under zero-order hold, fractional delays included, by THE SAME
// code as the plants: sim/lti's discretise_zoh / simulate_term (see sim/lti/README.md). This
// header adds what identification needs on top: a guard for vanishing time constants, the
// taps by lag (to differentiate them across a change of the whole-sample delay), and the
// all-pole filter of the sensitivity equations.

#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

#include "sim/lti/discretise.hpp"
#include "sim/lti/element.hpp"

namespace excite::host {

enum class Structure {
  first_order,
  two_poles,
  two_poles_zero,
  integrator,
  underdamped,
  underdamped_lag_zero,
};
inline constexpr int kStructures = 6;

/// "first_order", "two_poles", … (the names --structure and the model file use).
const char* to_string(Structure s);
/// The structure named `name`; nullopt for an unknown name.
std::optional<Structure> structure_from_string(std::string_view name);

/// Parameter order used for `at_bound`, covariance matrices and ElementModel::operator[].
enum Parameter : int {
  kGain = 0,
  kDelay = 1,
  kTp1 = 2,
  kTp2 = 3,
  kZero = 4,
  kNatural = 5,
  kDamping = 6,
};
inline constexpr int kParameters = 7;

/// The smallest damping ratio fitted (an oscillation that decays by 27 % per period).
inline constexpr double kMinDamping = 0.05;

/// Short name of a parameter: "K", "Td", "Tp1", "Tp2", "Tz", "Tn", "zeta".
const char* parameter_name(Parameter p);

/// The parameters a structure estimates, in Parameter order (K and Td always).
std::span<const int> free_parameters(Structure s);
bool is_free(Structure s, int parameter);

/// One element: the structure and its parameters. The parameters a structure does not
/// estimate hold their neutral values (Tz = T2 = Tn = 0, ζ = 1). Aggregate order keeps
/// ElementModel{K, Td, T1, T2} a two_poles element.
struct ElementModel {
  double gain = 0.0;         // K (output units per input unit; per minute for an integrator)
  double delay_min = 0.0;    // Td ≥ 0
  double tau1_min = 0.0;     // T1 ≥ 0
  double tau2_min = 0.0;     // T2 ≥ 0
  double zero_min = 0.0;     // Tz, either sign
  double natural_min = 0.0;  // Tn ≥ 0
  double damping = 1.0;      // ζ, 0 < ζ ≤ 1
  Structure structure = Structure::two_poles;

  double& operator[](int p);
  double operator[](int p) const;
  /// G(0): K, or ±inf for an integrator (NaN gain stays NaN).
  double static_gain() const;
};

/// Throws std::invalid_argument "PARAMETER = VALUE, expected RANGE" for a parameter that is
/// not finite or outside its range (T's ≥ 0, 0 < ζ ≤ 1).
void check_element(const ElementModel& g);

/// Time after which the element's step response is within about 0.1 % of its final value
/// (an integrator's: of its final slope): T_d + 7 (T_p1 + T_p2 + T_n/ζ + |T_z|).
double settling_time_min(const ElementModel& g);

/// The same element with the parameters `s` does not estimate set to their neutral values
/// and the structure set to s; the ones it shares are kept (a start for a fit in s).
ElementModel with_structure(ElementModel g, Structure s);

/// Time constants below this fraction of T are treated as exactly zero (the first-order or
/// static limit, which the element reaches continuously): the change in the response is
/// below ~1e-7 relative, and sim/lti's realisation loses accuracy for T_p ≪ T.
inline constexpr double kVanishingTimeConstant = 1e-7;

/// Exact ZOH discretisation at sample time T (minutes) via sim::discretise_zoh, with time
/// constants below kVanishingTimeConstant·T set to 0. Throws std::invalid_argument naming
/// the parameter for a value outside its range or not finite.
sim::DiscreteTerm discretise(const ElementModel& g, double sample_time_min);

/// The element as a continuous sim::Term (for sim::TransferMatrix and the export formats),
/// vanishing time constants dropped as in discretise().
sim::Term to_term(const ElementModel& g, double sample_time_min);

/// y = G u for k = 0 … N−1 from rest; u.size() == y.size().
void simulate(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y);

/// The element as y(k) = −Σ a_i y(k−i) + Σ_m b_m u(k − m) with the taps b_m listed for lags
/// m = first_lag … first_lag + kLagWindow − 1 (zero where the element has none).
inline constexpr std::size_t kLagWindow = 8;
inline constexpr std::size_t kMaxPoles = 3;
struct LagTaps {
  std::array<double, kMaxPoles> a{};  // a1, a2, a3
  std::array<double, kLagWindow> b{};
};
/// Precondition: the element's taps lie inside the window (its whole-sample delay d and the
/// up to four further taps satisfy first_lag ≤ d and d + 4 < first_lag + kLagWindow).
LagTaps lag_taps(const ElementModel& g, double sample_time_min, std::size_t first_lag);
/// The same taps from the element's discretisation `d` (discretise(g, T)), computed once.
LagTaps lag_taps(const sim::DiscreteTerm& d, std::size_t first_lag);

/// In place x ← x / (1 + a1 q⁻¹ + a2 q⁻² + a3 q⁻³), from rest.
void all_pole_filter(const std::array<double, kMaxPoles>& a, std::span<double> x);

}  // namespace excite::host
