// SPDX-License-Identifier: MIT
#pragma once
// Continuous transfer-function elements with dead time (SPEC §7). Time is in minutes
// everywhere: time constants, delays and frequencies (rad/min).
//
// An element is a sum of terms; each term is
//   gain · Π zeros_i(s)^k_i / Π poles_j(s)^l_j · e^{−s·delay_min}
// with every factor a real polynomial in s. Keeping the factors (rather than expanding)
// lets the poles of a repeated factor such as (34.5s+1)^2 be computed exactly.

#include <complex>
#include <string>
#include <vector>

namespace excite::sim {

/// Real polynomial in s, coefficients in ascending powers: {1, 33} is 33s + 1.
using Polynomial = std::vector<double>;

/// One polynomial factor raised to a positive integer power.
struct Factor {
  Polynomial poly;
  int power = 1;
};

/// gain · Π zeros / Π poles · e^{−s·delay_min}.
struct Term {
  double gain = 0.0;
  std::vector<Factor> zeros;
  std::vector<Factor> poles;
  double delay_min = 0.0;

  /// Degree of the expanded numerator and denominator.
  int numerator_degree() const;
  int denominator_degree() const;
  /// Expanded numerator gain·Π zeros and denominator Π poles (ascending powers).
  Polynomial numerator() const;
  Polynomial denominator() const;
  /// Roots of the denominator (each repeated as often as its multiplicity), 1/min.
  std::vector<std::complex<double>> pole_locations() const;
  /// G(0); +/−inf when a pole sits at s = 0.
  double static_gain() const;
  /// G(jω), ω in rad/min.
  std::complex<double> frequency_response(double omega_rad_per_min) const;
};

/// Options for checking an element once parsed.
struct ElementRules {
  /// Accept poles with Re(p) ≥ 0 (integrators, unstable plants). Off by default.
  bool allow_unstable = false;
};

/// A sum of terms. The zero element has no terms.
class Element {
 public:
  Element() = default;
  Element(std::vector<Term> terms, std::string text)
      : terms_(std::move(terms)), text_(std::move(text)) {}

  const std::vector<Term>& terms() const { return terms_; }
  /// The text the element was parsed from ("" when built in code).
  const std::string& text() const { return text_; }
  bool is_zero() const { return terms_.empty(); }

  double static_gain() const;
  std::complex<double> frequency_response(double omega_rad_per_min) const;

 private:
  std::vector<Term> terms_;
  std::string text_;
};

/// Evaluates p at a complex point.
std::complex<double> evaluate(const Polynomial& p, std::complex<double> s);
/// Product of two polynomials.
Polynomial multiply(const Polynomial& a, const Polynomial& b);
/// Degree ignoring zero leading coefficients (−1 for the zero polynomial).
int degree(const Polynomial& p);
/// Roots of p (degree ≥ 1); closed forms for degree 1 and 2, companion eigenvalues above.
std::vector<std::complex<double>> roots(const Polynomial& p);

}  // namespace excite::sim
