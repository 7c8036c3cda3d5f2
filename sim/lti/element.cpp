// SPDX-License-Identifier: MIT
#include "sim/lti/element.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::sim {

std::complex<double> evaluate(const Polynomial& p, std::complex<double> s) {
  std::complex<double> acc = 0.0;
  for (auto it = p.rbegin(); it != p.rend(); ++it) acc = acc * s + *it;
  return acc;
}

Polynomial multiply(const Polynomial& a, const Polynomial& b) {
  if (a.empty() || b.empty()) return {};
  Polynomial out(a.size() + b.size() - 1, 0.0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (std::size_t j = 0; j < b.size(); ++j) out[i + j] += a[i] * b[j];
  }
  return out;
}

int degree(const Polynomial& p) {
  for (std::size_t i = p.size(); i > 0; --i) {
    if (p[i - 1] != 0.0) return static_cast<int>(i) - 1;
  }
  return -1;
}

std::vector<std::complex<double>> roots(const Polynomial& p) {
  const int n = degree(p);
  if (n < 1) return {};
  const auto un = static_cast<std::size_t>(n);
  if (n == 1) return {{-p[0] / p[1], 0.0}};
  if (n == 2) {
    // Numerically stable quadratic formula (no cancellation between −b and √disc).
    const double a = p[2];
    const double b = p[1];
    const double c = p[0];
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
      if (q == 0.0) return {{0.0, 0.0}, {0.0, 0.0}};
      return {{q / a, 0.0}, {c / q, 0.0}};
    }
    const double re = -b / (2.0 * a);
    const double im = std::sqrt(-disc) / (2.0 * a);
    return {{re, im}, {re, -im}};
  }
  // Companion matrix of the monic polynomial.
  Eigen::MatrixXd companion = Eigen::MatrixXd::Zero(n, n);
  for (int i = 1; i < n; ++i) companion(i, i - 1) = 1.0;
  for (int i = 0; i < n; ++i) companion(i, n - 1) = -p[static_cast<std::size_t>(i)] / p[un];
  const Eigen::VectorXcd ev = companion.eigenvalues();
  return {ev.data(), ev.data() + ev.size()};
}

namespace {

Polynomial expand(const std::vector<Factor>& factors, double scale) {
  Polynomial out{scale};
  for (const Factor& f : factors) {
    for (int k = 0; k < f.power; ++k) out = multiply(out, f.poly);
  }
  return out;
}

int expanded_degree(const std::vector<Factor>& factors) {
  int d = 0;
  for (const Factor& f : factors) d += degree(f.poly) * f.power;
  return d;
}

}  // namespace

int Term::numerator_degree() const {
  return expanded_degree(zeros);
}
int Term::denominator_degree() const {
  return expanded_degree(poles);
}
Polynomial Term::numerator() const {
  return expand(zeros, gain);
}
Polynomial Term::denominator() const {
  return expand(poles, 1.0);
}

std::vector<std::complex<double>> Term::pole_locations() const {
  std::vector<std::complex<double>> out;
  for (const Factor& f : poles) {
    const auto r = roots(f.poly);
    for (int k = 0; k < f.power; ++k) out.insert(out.end(), r.begin(), r.end());
  }
  return out;
}

double Term::static_gain() const {
  double num = gain;
  for (const Factor& f : zeros) num *= std::pow(f.poly.empty() ? 0.0 : f.poly[0], f.power);
  double den = 1.0;
  for (const Factor& f : poles) den *= std::pow(f.poly.empty() ? 0.0 : f.poly[0], f.power);
  if (den == 0.0) {
    return num == 0.0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), num);
  }
  return num / den;
}

std::complex<double> Term::frequency_response(double omega_rad_per_min) const {
  const std::complex<double> s{0.0, omega_rad_per_min};
  std::complex<double> g = gain;
  for (const Factor& f : zeros) g *= std::pow(evaluate(f.poly, s), f.power);
  for (const Factor& f : poles) g /= std::pow(evaluate(f.poly, s), f.power);
  return g * std::exp(-s * delay_min);
}

double Element::static_gain() const {
  double g = 0.0;
  for (const Term& t : terms_) g += t.static_gain();
  return g;
}

std::complex<double> Element::frequency_response(double omega_rad_per_min) const {
  std::complex<double> g = 0.0;
  for (const Term& t : terms_) g += t.frequency_response(omega_rad_per_min);
  return g;
}

}  // namespace excite::sim
