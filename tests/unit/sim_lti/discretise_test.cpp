// SPDX-License-Identifier: MIT
// Exact ZOH discretisation: the MathWorks c2d oracle and step responses of single elements
// against their closed forms at the sample instants. Under ZOH a step input is exactly a
// continuous step, so y(kT) = S(kT − θ) holds to rounding.
#include "sim/lti/discretise.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sim/lti/parse_element.hpp"
#include "sim/lti/sopdt.hpp"

namespace excite::sim {
namespace {

DiscreteTerm discretise_text(const char* text, double t) {
  const Element e = parse_element(text);
  EXPECT_EQ(e.terms().size(), 1U);
  return discretise_zoh(e.terms().front(), t);
}

std::vector<double> step_response(const DiscreteTerm& d, std::size_t n) {
  const std::vector<double> u(n, 1.0);
  std::vector<double> y(n);
  simulate_term(d, u.data(), y.data(), n);
  return y;
}

// Compares y(kT) with S(kT − θ) (S = 0 for negative time) for k = 0 … n−1.
void expect_step_matches(const char* text, double t, std::size_t n,
                         const std::function<double(double)>& closed_form, double delay,
                         double tol = 1e-12) {
  const std::vector<double> y = step_response(discretise_text(text, t), n);
  for (std::size_t k = 0; k < n; ++k) {
    const double time = static_cast<double>(k) * t - delay;
    const double expected = time <= 0.0 ? 0.0 : closed_form(time);
    ASSERT_NEAR(y[k], expected, tol) << text << " at k = " << k;
  }
}

// MathWorks c2d documentation: 10 e^{−0.25s}/(s²+3s+10) at T = 0.1 is
// z^−3 (0.01187 z² + 0.06408 z + 0.009721)/(z² − 1.655 z + 0.7408).
TEST(Discretise, MatchesTheMathWorksC2dExampleWithFractionalDelay) {
  const DiscreteTerm d = discretise_text("10 e^-0.25s / (s^2 + 3s + 10)", 0.1);
  EXPECT_EQ(d.delay_samples, 3);
  ASSERT_EQ(d.nb, 3);
  ASSERT_EQ(d.na, 3);
  const double b[] = {0.01187, 0.06408, 0.009721};
  const double a[] = {1.0, -1.655, 0.7408};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_NEAR(d.b[i], b[i], 5e-4 * std::abs(b[i]) + 1e-7) << "b" << i;
    EXPECT_NEAR(d.a[i], a[i], 5e-4 * std::abs(a[i])) << "a" << i;
  }
}

TEST(Discretise, FirstOrderStepIsOneMinusExponential) {
  expect_step_matches(
      "2.5/(7s+1)", 1.0, 60, [](double t) { return 2.5 * (1 - std::exp(-t / 7)); }, 0.0);
}

TEST(Discretise, FirstOrderWithFractionalDelayIsShiftedExactly) {
  expect_step_matches(
      "-4.17 e^-5.3s / (45s+1)", 1.0, 200, [](double t) { return -4.17 * (1 - std::exp(-t / 45)); },
      5.3);
}

TEST(Discretise, SecondOrderDistinctPoles) {
  expect_step_matches(
      "4.09 e^-1.3s / ((33s+1)(8.3s+1))", 1.0, 300,
      [](double t) {
        return 4.09 * (1 - (33 * std::exp(-t / 33) - 8.3 * std::exp(-t / 8.3)) / (33 - 8.3));
      },
      1.3);
}

TEST(Discretise, RepeatedPole) {
  expect_step_matches(
      "-0.05 e^-6s / (34.5s+1)^2", 1.0, 400,
      [](double t) { return -0.05 * (1 - (1 + t / 34.5) * std::exp(-t / 34.5)); }, 6.0);
}

// Found by tests/fuzz/element_fuzz: six poles at −113/min and T = 1 min overflow the
// matrix exponential; the coefficients came back NaN and a plant simulated NaN. Refused now.
TEST(Discretise, PolesFarFasterThanTheSampleTimeAreRefusedNotNaN) {
  const Element e = parse_element("1 / (113+s)^6");
  try {
    discretise_zoh(e.terms().front(), 1.0);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("non-finite coefficients"), std::string::npos)
        << error.what();
  }
}

TEST(Discretise, NumeratorZero) {
  // K(a s+1)/((τ1 s+1)(τ2 s+1)): S = K[1 − ((τ1−a)e^{−t/τ1} − (τ2−a)e^{−t/τ2})/(τ1−τ2)].
  expect_step_matches(
      "3(10s+1) e^-0.4s / ((20s+1)(4s+1))", 0.5, 400,
      [](double t) {
        return 3 * (1 - ((20 - 10) * std::exp(-t / 20) - (4 - 10) * std::exp(-t / 4)) / (20 - 4));
      },
      0.4);
}

TEST(Discretise, RightHalfPlaneZeroGivesInverseResponse) {
  expect_step_matches(
      "(-5s+1)/((10s+1)(2s+1))", 1.0, 100,
      [](double t) {
        return 1 - ((10 + 5) * std::exp(-t / 10) - (2 + 5) * std::exp(-t / 2)) / (10 - 2);
      },
      0.0);
}

TEST(Discretise, UnderdampedQuadratic) {
  const double wn = 1 / std::sqrt(17.4);
  const double zeta = 3 / 17.4 / (2 * wn);
  const double wd = wn * std::sqrt(1 - zeta * zeta);
  expect_step_matches(
      "1/(17.4s^2+3s+1)", 0.25, 400,
      [&](double t) {
        return 1 - std::exp(-zeta * wn * t) *
                       (std::cos(wd * t) + zeta / std::sqrt(1 - zeta * zeta) * std::sin(wd * t));
      },
      0.0);
}

// The case study's third-order element with a zero and a fractional delay, against the
// residue form S(t) = G(0) + Σ N(p)/(p·D'(p)) e^{pt} over its distinct poles p.
TEST(Discretise, ThirdOrderWithZeroAndFractionalDelayMatchesResidues) {
  using C = std::complex<double>;
  // N = 140 s + 14, D = (45s+1)(17.4s²+3s+1) = 783 s³ + 152.4 s² + 48 s + 1.
  const double disc = std::sqrt(4 * 17.4 - 9.0);
  const C poles[] = {C(-1.0 / 45, 0), C(-3.0, disc) / 34.8, C(-3.0, -disc) / 34.8};
  expect_step_matches(
      "14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))", 1.0, 400,
      [&](double t) {
        C s = 14.0;
        for (const C& p : poles) {
          s += (140.0 * p + 14.0) / (p * (2349.0 * p * p + 304.8 * p + 48.0)) * std::exp(p * t);
        }
        return s.real();
      },
      0.02, 1e-12 * 14.0);  // 1e-12 relative to the gain
}

TEST(Discretise, PureDelayOfFractionalLengthRoundsUpUnderZeroOrderHold) {
  const DiscreteTerm d = discretise_text("-0.56 e^-2.5s", 1.0);
  EXPECT_EQ(d.delay_samples, 3);
  EXPECT_EQ(d.order(), 0);
  expect_step_matches(
      "-0.56 e^-2.5s", 1.0, 10, [](double) { return -0.56; }, 2.5);
}

TEST(Discretise, WholeSampleDelayIsSnappedDespiteRounding) {
  // 0.3 / 0.1 is 2.9999999999999996 in binary floating point.
  const DelaySplit s = split_delay(0.3, 0.1);
  EXPECT_EQ(s.whole_samples, 3);
  EXPECT_EQ(s.fraction_min, 0.0);
  const DelaySplit f = split_delay(1.25, 0.5);
  EXPECT_EQ(f.whole_samples, 2);
  EXPECT_NEAR(f.fraction_min, 0.25, 1e-15);
}

TEST(Discretise, KeepsTheStaticGain) {
  for (const char* text : {"14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))", "87.8/(194s+1)",
                           "-5.65 e^-8.72s / (250s+1)^2", "2(3s+1)/(5s+1)"}) {
    const Element e = parse_element(text);
    const DiscreteTerm d = discretise_zoh(e.terms().front(), 1.0);
    EXPECT_NEAR(d.static_gain(), e.static_gain(), 1e-10 * std::abs(e.static_gain())) << text;
  }
}

TEST(Discretise, BiproperTermPassesTheInputThroughAtOnce) {
  // 2(3s+1)/(5s+1) = 2[3/5 + (2/5)/(5s+1)]: S = 2[1 − (2/5) e^{−t/5}], S(0) = 1.2.
  const std::vector<double> y = step_response(discretise_text("2(3s+1)/(5s+1)", 1.0), 20);
  for (std::size_t k = 0; k < y.size(); ++k) {
    EXPECT_NEAR(y[k], 2 * (1 - 0.4 * std::exp(-static_cast<double>(k) / 5)), 1e-12);
  }
}

TEST(Discretise, BiproperTermWithFractionalDelay) {
  expect_step_matches(
      "2(3s+1) e^-0.4s / (5s+1)", 1.0, 30,
      [](double t) { return 2 * (1 - 0.4 * std::exp(-t / 5)); }, 0.4);
}

TEST(Discretise, IntegratorIsARampWhenUnstableIsAllowed) {
  ElementRules allow;
  allow.allow_unstable = true;
  const Term t = parse_element("0.5 e^-1.25s / s", "x", allow).terms().front();
  const DiscreteTerm d = discretise_zoh(t, 0.5);
  const std::vector<double> y = step_response(d, 40);
  for (std::size_t k = 0; k < y.size(); ++k) {
    EXPECT_NEAR(y[k], 0.5 * std::max(0.0, static_cast<double>(k) * 0.5 - 1.25), 1e-12) << k;
  }
}

TEST(Discretise, RefusesTermsAboveTheMaximumOrder) {
  const Term t = parse_element("1/(s+1)^7").terms().front();
  EXPECT_THROW((void)discretise_zoh(t, 1.0), std::invalid_argument);
}

TEST(Discretise, RejectsBadSampleTimes) {
  const Term t = parse_element("1/(s+1)").terms().front();
  EXPECT_THROW((void)discretise_zoh(t, 0.0), std::invalid_argument);
  EXPECT_THROW((void)discretise_zoh(t, -1.0), std::invalid_argument);
  EXPECT_THROW((void)discretise_zoh(t, std::nan("")), std::invalid_argument);
}

TEST(Sopdt, EqualsTheParsedElement) {
  const SopdtParameters p{4.49, 0.6, 48, 6.3};
  const DiscreteTerm fast = discretise_sopdt(p, 1.0);
  const DiscreteTerm parsed = discretise_text("4.49 e^-0.6s / ((48s+1)(6.3s+1))", 1.0);
  ASSERT_EQ(fast.delay_samples, parsed.delay_samples);
  ASSERT_EQ(fast.nb, parsed.nb);
  ASSERT_EQ(fast.na, parsed.na);
  for (std::size_t i = 0; i < kMaxCoefficients; ++i) {
    EXPECT_NEAR(fast.b[i], parsed.b[i], 1e-14);
    EXPECT_NEAR(fast.a[i], parsed.a[i], 1e-14);
  }
}

TEST(Sopdt, EqualTimeConstantsAreTheRepeatedPole) {
  const Eigen::VectorXd y = simulate_sopdt({2.0, 3.5, 12.0, 12.0}, 1.0, Eigen::VectorXd::Ones(100));
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    const double t = static_cast<double>(k) - 3.5;
    const double expected = t <= 0 ? 0.0 : 2.0 * (1 - (1 + t / 12) * std::exp(-t / 12));
    ASSERT_NEAR(y(k), expected, 1e-12) << k;
  }
}

TEST(Sopdt, ZeroTimeConstantsDropThePoles) {
  const Eigen::VectorXd y = simulate_sopdt({-1.5, 2.0, 0.0, 0.0}, 1.0, Eigen::VectorXd::Ones(6));
  EXPECT_EQ(y(1), 0.0);
  EXPECT_EQ(y(2), -1.5);
  const Eigen::VectorXd y1 = simulate_sopdt({1.0, 0.0, 0.0, 9.0}, 1.0, Eigen::VectorXd::Ones(30));
  EXPECT_NEAR(y1(29), 1 - std::exp(-29.0 / 9.0), 1e-12);
}

TEST(Sopdt, RejectsNegativeOrNonFiniteParametersNamingThem) {
  try {
    (void)discretise_sopdt({1.0, 0.0, -3.0, 1.0}, 1.0);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Tp1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("-3"), std::string::npos) << e.what();
  }
  EXPECT_THROW((void)discretise_sopdt({1.0, -0.1, 1.0, 1.0}, 1.0), std::invalid_argument);
  EXPECT_THROW((void)discretise_sopdt({std::nan(""), 0.0, 1.0, 1.0}, 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace excite::sim
