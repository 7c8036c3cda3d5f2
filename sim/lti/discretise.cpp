// SPDX-License-Identifier: MIT
#include "sim/lti/discretise.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/MatrixFunctions>

#include "sim/lti/parse_element.hpp"

namespace excite::sim {
namespace {

constexpr int kMaxAugmented = kMaxTermOrder + 1;
// Dynamic size with a fixed capacity: lives on the stack, never allocates.
using SmallMatrix =
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxAugmented, kMaxAugmented>;
using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxAugmented, 1>;
using SmallRow = Eigen::Matrix<double, 1, Eigen::Dynamic, Eigen::RowMajor, 1, kMaxAugmented>;

void check_sample_time(double t) {
  if (!std::isfinite(t) || t <= 0.0) {
    throw std::invalid_argument("sample time " + std::to_string(t) +
                                " min, expected a finite value > 0");
  }
}

int degree_of(std::span<const double> p) {
  for (std::size_t i = p.size(); i > 0; --i) {
    if (p[i - 1] != 0.0) return static_cast<int>(i) - 1;
  }
  return -1;
}

}  // namespace

double DiscreteTerm::static_gain() const {
  double sb = 0.0;
  double sa = 0.0;
  for (int i = 0; i < nb; ++i) sb += b[static_cast<std::size_t>(i)];
  for (int i = 0; i < na; ++i) sa += a[static_cast<std::size_t>(i)];
  return sb / sa;
}

DelaySplit split_delay(double delay_min, double sample_time_min) {
  check_sample_time(sample_time_min);
  if (!std::isfinite(delay_min) || delay_min < 0.0) {
    throw std::invalid_argument("delay " + std::to_string(delay_min) +
                                " min, expected a finite value ≥ 0");
  }
  const double samples = delay_min / sample_time_min;
  if (samples > kMaxDelaySamples) {
    throw std::invalid_argument("delay " + std::to_string(delay_min) + " min at sample time " +
                                std::to_string(sample_time_min) + " min, expected at most " +
                                std::to_string(kMaxDelaySamples) + " samples");
  }
  double whole = std::floor(samples);
  double rest = samples - whole;
  constexpr double kSnap = 1e-9;
  if (rest < kSnap) {
    rest = 0.0;
  } else if (rest > 1.0 - kSnap) {
    whole += 1.0;
    rest = 0.0;
  }
  return {static_cast<int>(whole), rest * sample_time_min};
}

DiscreteTerm discretise_zoh(std::span<const double> num, std::span<const double> den,
                            std::span<const std::complex<double>> poles, double delay_min,
                            double sample_time_min) {
  const double T = sample_time_min;
  const DelaySplit split = split_delay(delay_min, T);
  const int n = degree_of(den);
  if (n < 0) throw std::invalid_argument("denominator, expected a non-zero polynomial");
  if (n > kMaxTermOrder) {
    throw std::invalid_argument("denominator degree " + std::to_string(n) + ", expected at most " +
                                std::to_string(kMaxTermOrder));
  }
  if (degree_of(num) > n) {
    throw std::invalid_argument("numerator degree " + std::to_string(degree_of(num)) +
                                ", expected at most the denominator degree " + std::to_string(n));
  }
  if (static_cast<int>(poles.size()) != n) {
    throw std::invalid_argument(std::to_string(poles.size()) +
                                " poles given for denominator degree " + std::to_string(n));
  }
  const auto un = static_cast<std::size_t>(n);
  const double lead = den[un];
  const double feedthrough = num.size() > un ? num[un] / lead : 0.0;
  const double f = split.fraction_min;
  const bool fractional = f > 0.0;

  // Markov parameters h[0..n+1] of the delay-free-by-m system.
  std::array<double, kMaxCoefficients> h{};
  h[fractional ? 1 : 0] = feedthrough;
  if (n > 0) {
    // Controllable canonical form of R(s)/D(s), R = N − feedthrough·D, D monic.
    SmallMatrix m = SmallMatrix::Zero(n + 1, n + 1);
    for (int i = 0; i + 1 < n; ++i) m(i, i + 1) = 1.0;
    for (int i = 0; i < n; ++i) m(n - 1, i) = -den[static_cast<std::size_t>(i)] / lead;
    m(n - 1, n) = 1.0;  // B = e_n
    SmallRow c(n);
    for (int i = 0; i < n; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      const double ni = ui < num.size() ? num[ui] : 0.0;
      c(i) = (ni - feedthrough * den[ui]) / lead;
    }
    const SmallMatrix e_main = (m * (T - f)).exp();
    const SmallMatrix phi_main = e_main.topLeftCorner(n, n);
    const SmallVector gamma0 = e_main.topRightCorner(n, 1);
    SmallMatrix phi = phi_main;
    SmallVector gamma1 = SmallVector::Zero(n);
    if (fractional) {
      const SmallMatrix e_frac = (m * f).exp();
      gamma1 = phi_main * e_frac.topRightCorner(n, 1);
      phi = phi_main * e_frac.topLeftCorner(n, n);
    }
    // Impulse: x(1) = Γ0, x(2) = Φ Γ0 + Γ1, x(k) = Φ x(k−1).
    SmallVector x = gamma0;
    for (int k = 1; k <= n + 1; ++k) {
      if (k == 2) x = phi * x + gamma1;
      if (k > 2) x = phi * x;
      h[static_cast<std::size_t>(k)] += c.dot(x);
    }
  }

  DiscreteTerm out;
  out.delay_samples = split.whole_samples;
  // A(z^−1) = Π (1 − e^{p T} z^−1), accumulated in complex arithmetic.
  std::array<std::complex<double>, kMaxCoefficients> ac{};
  ac[0] = 1.0;
  for (int i = 0; i < n; ++i) {
    const std::complex<double> zp = std::exp(poles[static_cast<std::size_t>(i)] * T);
    for (int j = i + 1; j >= 1; --j) {
      ac[static_cast<std::size_t>(j)] -= zp * ac[static_cast<std::size_t>(j - 1)];
    }
  }
  out.na = n + 1;
  for (int i = 0; i <= n; ++i)
    out.a[static_cast<std::size_t>(i)] = ac[static_cast<std::size_t>(i)].real();
  // B = A · H truncated: b_j = Σ_i a_i h_{j−i}.
  out.nb = fractional ? n + 2 : n + 1;
  for (int j = 0; j < out.nb; ++j) {
    double s = 0.0;
    for (int i = 0; i <= j && i <= n; ++i) {
      s += out.a[static_cast<std::size_t>(i)] * h[static_cast<std::size_t>(j - i)];
    }
    out.b[static_cast<std::size_t>(j)] = s;
  }
  // A term whose matrix exponential overflows (poles far faster than the sample time, e.g.
  // 1/(s+113)^6 at T = 1 min) is refused by name rather than simulated as NaN.
  for (int j = 0; j < kMaxCoefficients; ++j) {
    const auto uj = static_cast<std::size_t>(j);
    if (!std::isfinite(out.b[uj]) || !std::isfinite(out.a[uj])) {
      throw std::invalid_argument(
          "discretisation at sample time " + std::to_string(T) +
          " min gives non-finite coefficients (poles too fast for the sample time), expected "
          "a shorter sample time or slower poles");
    }
  }
  // Leading exact zeros of b are whole-sample delays.
  while (out.nb > 1 && out.b[0] == 0.0) {
    for (int j = 1; j < out.nb; ++j) {
      out.b[static_cast<std::size_t>(j - 1)] = out.b[static_cast<std::size_t>(j)];
    }
    out.b[static_cast<std::size_t>(out.nb - 1)] = 0.0;
    --out.nb;
    ++out.delay_samples;
  }
  return out;
}

DiscreteTerm discretise_zoh(const Term& term, double sample_time_min) {
  ElementRules rules;
  rules.allow_unstable = true;  // stability was the parser's decision; a term is taken as given
  const std::string problem = check_term(term, rules);
  if (!problem.empty()) throw std::invalid_argument("term: " + problem);
  const int n = term.denominator_degree();
  if (n > kMaxTermOrder) {
    throw std::invalid_argument("term denominator degree " + std::to_string(n) +
                                ", expected at most " + std::to_string(kMaxTermOrder));
  }
  const Polynomial num = term.numerator();
  const Polynomial den = term.denominator();
  const std::vector<std::complex<double>> poles = term.pole_locations();
  return discretise_zoh(num, den, poles, term.delay_min, sample_time_min);
}

}  // namespace excite::sim
