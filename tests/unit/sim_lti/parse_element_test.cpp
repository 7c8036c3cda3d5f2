// SPDX-License-Identifier: MIT
// The element grammar: the forms of SPEC §7 parse to the right factors, and malformed or
// rejected text fails with the context, the text, the position and what was expected.
#include "sim/lti/parse_element.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <string>

namespace excite::sim {
namespace {

std::complex<double> g_at(const char* text, double omega) {
  return parse_element(text).frequency_response(omega);
}

TEST(ParseElement, GainDelayAndProductOfFirstOrderFactors) {
  const Element e = parse_element("4.09 e^-1.3s / ((33s+1)(8.3s+1))");
  ASSERT_EQ(e.terms().size(), 1U);
  const Term& t = e.terms().front();
  EXPECT_DOUBLE_EQ(t.gain, 4.09);
  EXPECT_DOUBLE_EQ(t.delay_min, 1.3);
  EXPECT_TRUE(t.zeros.empty());
  ASSERT_EQ(t.poles.size(), 2U);
  EXPECT_EQ(t.poles[0].poly, (Polynomial{1.0, 33.0}));
  EXPECT_EQ(t.poles[1].poly, (Polynomial{1.0, 8.3}));
  EXPECT_DOUBLE_EQ(e.static_gain(), 4.09);
}

TEST(ParseElement, ZeroAndUnderdampedQuadratic) {
  const Element e = parse_element("14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))");
  const Term& t = e.terms().front();
  EXPECT_DOUBLE_EQ(t.gain, 14.0);
  ASSERT_EQ(t.zeros.size(), 1U);
  EXPECT_EQ(t.zeros[0].poly, (Polynomial{1.0, 10.0}));
  ASSERT_EQ(t.poles.size(), 2U);
  EXPECT_EQ(t.poles[1].poly, (Polynomial{1.0, 3.0, 17.4}));
  EXPECT_EQ(t.numerator_degree(), 1);
  EXPECT_EQ(t.denominator_degree(), 3);
  // G(jω) against the formula evaluated by hand.
  const double w = 0.07;
  const std::complex<double> s{0.0, w};
  const std::complex<double> expected = 14.0 * (10.0 * s + 1.0) * std::exp(-0.02 * s) /
                                        ((45.0 * s + 1.0) * (17.4 * s * s + 3.0 * s + 1.0));
  EXPECT_NEAR(std::abs(e.frequency_response(w) - expected), 0.0, 1e-12);
}

TEST(ParseElement, RepeatedPoleKeepsItsPower) {
  const Term t = parse_element("1.73 e^-18s / (13s+1)^2").terms().front();
  ASSERT_EQ(t.poles.size(), 1U);
  EXPECT_EQ(t.poles[0].power, 2);
  const auto p = t.pole_locations();
  ASSERT_EQ(p.size(), 2U);
  EXPECT_DOUBLE_EQ(p[0].real(), -1.0 / 13.0);
  EXPECT_DOUBLE_EQ(p[1].real(), -1.0 / 13.0);
}

TEST(ParseElement, StaticGainWithDelay) {
  const Term t = parse_element("-0.56 e^-1s").terms().front();
  EXPECT_DOUBLE_EQ(t.gain, -0.56);
  EXPECT_DOUBLE_EQ(t.delay_min, 1.0);
  EXPECT_TRUE(t.poles.empty());
}

TEST(ParseElement, SumOfTerms) {
  const Element e = parse_element("-87.8/(194s+1) + 1.4/(15s+1)");
  ASSERT_EQ(e.terms().size(), 2U);
  EXPECT_DOUBLE_EQ(e.terms()[0].gain, -87.8);
  EXPECT_DOUBLE_EQ(e.terms()[1].gain, 1.4);
  EXPECT_DOUBLE_EQ(e.static_gain(), -86.4);
  EXPECT_DOUBLE_EQ(parse_element("-108.2/(194s+1) - 1.4/(15s+1)").static_gain(), -109.6);
}

TEST(ParseElement, EquivalentSpellingsGiveTheSameElement) {
  const double w = 0.13;
  const auto reference = g_at("4.09 e^-1.3s / ((33s+1)(8.3s+1))", w);
  for (const char* text :
       {"4.09e^-1.3s/((33s+1)(8.3s+1))", "4.09 * e^{-1.3s} / ((33s + 1) * (8.3s + 1))",
        "4.09 exp(-1.3s) / ((33*s+1)(8.3*s+1))", "4.09/((33s+1)(8.3s+1)) e^(-1.3s)",
        "4.09 / (33s+1) / (8.3s+1) e^-1.3s", "409e-2 e^-1.3s / (273.9s^2 + 41.3s + 1)"}) {
    EXPECT_NEAR(std::abs(g_at(text, w) - reference), 0.0, 1e-12) << text;
  }
}

TEST(ParseElement, ZeroAndDelayWithoutCoefficient) {
  EXPECT_TRUE(parse_element("0").is_zero());
  EXPECT_TRUE(parse_element(" 0 e^-3s / (5s+1) ").is_zero());
  const Term t = parse_element("e^-s/(s+1)").terms().front();
  EXPECT_DOUBLE_EQ(t.gain, 1.0);
  EXPECT_DOUBLE_EQ(t.delay_min, 1.0);
}

// Expects a throw whose message contains every fragment, and the given 1-based position.
void expect_error(const char* text, std::size_t position,
                  std::initializer_list<const char*> fragments, const ElementRules& rules = {}) {
  try {
    (void)parse_element(text, "G row 2 (y2), column 3 (u3)", rules);
    FAIL() << "expected an error for \"" << text << "\"";
  } catch (const ElementSyntaxError& e) {
    const std::string what = e.what();
    EXPECT_EQ(e.position() + 1, position) << what;
    EXPECT_NE(what.find("G row 2 (y2), column 3 (u3)"), std::string::npos) << what;
    EXPECT_NE(what.find(std::string("\"") + text + "\""), std::string::npos) << what;
    EXPECT_NE(what.find("position " + std::to_string(position)), std::string::npos) << what;
    for (const char* f : fragments) EXPECT_NE(what.find(f), std::string::npos) << what;
  }
}

TEST(ParseElementErrors, UnbalancedParenthesis) {
  expect_error("4.09 / ((33s+1)(8.3s+1)", 24, {"expected ')'"});
}

TEST(ParseElementErrors, MissingDenominator) {
  expect_error("4.09 /", 7, {"denominator"});
}

TEST(ParseElementErrors, PositiveDelayExponent) {
  expect_error("2 e^1.3s/(s+1)", 5, {"'-'"});
}

TEST(ParseElementErrors, NegativeDelay) {
  expect_error("2 e^--1.3s/(s+1)", 6, {"'s'"});
}

TEST(ParseElementErrors, TwoDelaysInOneTerm) {
  expect_error("2 e^-1s e^-2s/(s+1)", 9, {"only one delay"});
}

TEST(ParseElementErrors, NegativeTimeConstantIsARightHalfPlanePole) {
  expect_error("3 / (-5s+1)", 1, {"pole at s = 0.2", "time constant -5 min", "allow_unstable"});
  ElementRules allow;
  allow.allow_unstable = true;
  EXPECT_NO_THROW((void)parse_element("3 / (-5s+1)", "x", allow));
}

TEST(ParseElementErrors, IntegratorNeedsTheFlag) {
  expect_error("1/s", 1, {"pole at s = 0"});
  ElementRules allow;
  allow.allow_unstable = true;
  EXPECT_TRUE(std::isinf(parse_element("1/s", "x", allow).static_gain()));
}

TEST(ParseElementErrors, DelayInsideTheDenominatorParentheses) {
  expect_error("2/((s+1) e^-3s)", 10, {"denominator"});
}

TEST(ParseElementErrors, PowerOfAGroupWithADelay) {
  expect_error("((3s+1) e^-2s)^2 / ((s+1)(2s+1))", 15, {"power of a group holding a delay"});
}

TEST(ParseElementErrors, ImproperTerm) {
  expect_error("(10s+1)", 1, {"improper"});
}

TEST(ParseElementErrors, GarbageAfterATerm) {
  expect_error("2/(s+1) ]", 9, {"expected '+', '-' or the end"});
}

TEST(ParseElementErrors, NotANumber) {
  expect_error("nan/(s+1)", 1, {"expected a number"});
  expect_error("1e999/(s+1)", 1, {"out of range"});
}

TEST(ParseElementErrors, EmptyText) {
  expect_error("  ", 3, {"expected an element"});
}

TEST(ParseElementErrors, DivisionByZero) {
  expect_error("1/(0)", 4, {"zero polynomial"});
}

}  // namespace
}  // namespace excite::sim

namespace excite::sim {
namespace {

// Every single-character deletion, duplication and replacement of valid elements either
// parses or fails with ElementSyntaxError pointing inside (or just past) the text — never
// another exception, a crash or an out-of-range position (run under ASan in CI).
TEST(ParseElementErrors, MutatedTextFailsCleanly) {
  const std::string alphabet = "0123456789.+-*/^()es{} x";
  int parsed = 0;
  int refused = 0;
  for (const std::string base :
       {"14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))", "87.8/(194s+1) + 1.4/(15s+1)",
        "-0.56 e^{-1s}", "4.09 exp(-1.3s)/(33s+1)^2"}) {
    std::vector<std::string> variants;
    for (std::size_t i = 0; i < base.size(); ++i) {
      variants.push_back(base.substr(0, i) + base.substr(i + 1));
      variants.push_back(base.substr(0, i + 1) + base.substr(i));
      for (char c : alphabet) {
        std::string v = base;
        v[i] = c;
        variants.push_back(v);
      }
    }
    for (const std::string& v : variants) {
      try {
        (void)parse_element(v);
        ++parsed;
      } catch (const ElementSyntaxError& e) {
        EXPECT_LE(e.position(), v.size()) << v;
        ++refused;
      }
    }
  }
  EXPECT_GT(parsed, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace excite::sim
