// SPDX-License-Identifier: MIT
#pragma once
// Exact zero-order-hold discretisation of one term with a delay of any length, fractional
// parts included (modified z-transform, done by augmenting the state with the previous
// input). Time in minutes.
//
// With the delay θ = m·T + f (m whole samples, 0 ≤ f < T) and ẋ = A x + B u(t − f),
// y = C x + D u(t − f), the input held over [kT, (k+1)T) gives
//   x(k+1) = Φ x(k) + Γ0 u(k) + Γ1 u(k−1),   Φ = e^{AT},
//   Γ0 = ∫_0^{T−f} e^{Aσ} dσ B,   Γ1 = e^{A(T−f)} ∫_0^{f} e^{Aσ} dσ B,
// (both from one Van Loan exponential of [[A, B], [0, 0]]). The result is
//   H(z) = z^{−delay_samples} (b0 + b1 z^−1 + …) / (1 + a1 z^−1 + …),
// with a = Π (1 − e^{p_i T} z^−1) over the continuous poles p_i and b from the Markov
// parameters of the system above. Nothing here allocates.

#include <array>
#include <complex>
#include <span>

#include "sim/lti/element.hpp"

namespace excite::sim {

/// Highest denominator degree of one term (the library plants need 3).
inline constexpr int kMaxTermOrder = 6;
/// Coefficient capacity: a fractional delay adds one numerator coefficient.
inline constexpr int kMaxCoefficients = kMaxTermOrder + 2;

/// z^{−delay_samples} B(z^−1)/A(z^−1); b[0..nb), a[0..na), a[0] = 1.
struct DiscreteTerm {
  int delay_samples = 0;
  int nb = 1;
  int na = 1;
  std::array<double, kMaxCoefficients> b{};
  std::array<double, kMaxCoefficients> a{1.0};

  /// Order of the difference equation: max(nb, na) − 1.
  int order() const { return (nb > na ? nb : na) - 1; }
  /// H(1) = Σb / Σa, equal to the continuous G(0) (ZOH keeps the static gain).
  double static_gain() const;
};

/// A delay θ split into whole samples and a remainder in minutes, 0 ≤ fraction_min < T.
/// Remainders within 1e-9·T of 0 or T are snapped (so 0.3 min at T = 0.1 is 3 samples).
struct DelaySplit {
  int whole_samples;
  double fraction_min;
};
DelaySplit split_delay(double delay_min, double sample_time_min);

/// Longest delay accepted, in samples (bounds the ring buffers).
inline constexpr int kMaxDelaySamples = 10'000'000;

/// Discretises num(s)/den(s)·e^{−s·delay_min} (ascending coefficients, num including the
/// gain, deg num ≤ deg den ≤ kMaxTermOrder) whose denominator roots are `poles`.
/// Throws std::invalid_argument for a bad sample time, delay or degree, and when the result
/// is not finite (poles far faster than the sample time overflow the matrix exponential).
DiscreteTerm discretise_zoh(std::span<const double> num, std::span<const double> den,
                            std::span<const std::complex<double>> poles, double delay_min,
                            double sample_time_min);

/// Discretises a checked term (see check_term). Throws std::invalid_argument.
DiscreteTerm discretise_zoh(const Term& term, double sample_time_min);

}  // namespace excite::sim
