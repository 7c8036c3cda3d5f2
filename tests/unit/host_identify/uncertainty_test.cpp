// SPDX-License-Identifier: MIT
// How far an identified model can be trusted, piece by piece: the linearised uncertainty of
// G(0)'s singular values, directions and principal minors (gain_uncertainty.hpp) against
// sampling and against closed forms; Ljung's residual tests (residuals.hpp) at their stated
// 1 % level; the grade rule (grade.hpp). The calibration over noise seeds of whole
// identifications is tests/integration/host_calibration.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "host/identify/gain_sensitivity.hpp"
#include "host/identify/gain_uncertainty.hpp"
#include "host/identify/grade.hpp"
#include "host/identify/residuals.hpp"
#include "sim/library/library.hpp"

namespace excite::host {
namespace {

// Row covariances: SE of each gain `relative` of |K| plus `floor`, correlation rho between
// neighbours of a row (a MISO fit's gains are correlated).
std::vector<Eigen::MatrixXd> row_covariances(const Eigen::MatrixXd& G, double relative,
                                             double floor, double rho) {
  std::vector<Eigen::MatrixXd> out;
  for (Eigen::Index j = 0; j < G.rows(); ++j) {
    Eigen::MatrixXd c(G.cols(), G.cols());
    for (Eigen::Index a = 0; a < G.cols(); ++a) {
      for (Eigen::Index b = 0; b < G.cols(); ++b) {
        const double sa = relative * std::abs(G(j, a)) + floor;
        const double sb = relative * std::abs(G(j, b)) + floor;
        c(a, b) = sa * sb * (a == b ? 1.0 : std::abs(a - b) == 1 ? rho : 0.0);
      }
    }
    out.push_back(c);
  }
  return out;
}

// Angle between two unit directions, sign-free, degrees.
double angle_deg(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return std::acos(std::min(1.0, std::abs(a.dot(b)))) * 180.0 / std::numbers::pi;
}

TEST(GainUncertainty, LinearisedSpreadOfSigmaAndDirectionsMatchesSamplingOnAlatiqi4x4) {
  const Eigen::MatrixXd G = sim::library_plant("alatiqi4x4").static_gain();
  const auto cov = row_covariances(G, 2e-3, 1e-4, 0.5);
  const GainUncertainty u = gain_uncertainty(G, cov);
  EXPECT_NEAR(u.singular_values(3), 0.1635, 5e-5);  // SPEC §7

  // Sampling: G + E, E drawn row by row from the stated covariances.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> z(0.0, 1.0);
  std::vector<Eigen::MatrixXd> chol;
  for (const auto& c : cov) chol.push_back(c.llt().matrixL());
  const Eigen::JacobiSVD<Eigen::MatrixXd> base(G, Eigen::ComputeFullU | Eigen::ComputeFullV);
  constexpr int kSamples = 20000;
  Eigen::VectorXd sigma_var = Eigen::VectorXd::Zero(4), v_ms = Eigen::VectorXd::Zero(4),
                  w_ms = Eigen::VectorXd::Zero(4);
  for (int s = 0; s < kSamples; ++s) {
    Eigen::MatrixXd Gs = G;
    for (Eigen::Index j = 0; j < 4; ++j) {
      Eigen::VectorXd e(4);
      for (Eigen::Index k = 0; k < 4; ++k) e(k) = z(rng);
      Gs.row(j) += (chol[static_cast<std::size_t>(j)] * e).transpose();
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Gs, Eigen::ComputeFullU | Eigen::ComputeFullV);
    for (Eigen::Index i = 0; i < 4; ++i) {
      const double d = svd.singularValues()(i) - base.singularValues()(i);
      sigma_var(i) += d * d / kSamples;
      const double av = angle_deg(svd.matrixV().col(i), base.matrixV().col(i));
      const double aw = angle_deg(svd.matrixU().col(i), base.matrixU().col(i));
      v_ms(i) += av * av / kSamples;
      w_ms(i) += aw * aw / kSamples;
    }
  }
  for (Eigen::Index i = 0; i < 4; ++i) {
    EXPECT_NEAR(u.singular_value_se(i), std::sqrt(sigma_var(i)), 0.05 * std::sqrt(sigma_var(i)))
        << "sigma " << i + 1;
    EXPECT_NEAR(u.input_angle_se_deg(i), std::sqrt(v_ms(i)), 0.05 * std::sqrt(v_ms(i)))
        << "v " << i + 1;
    EXPECT_NEAR(u.output_angle_se_deg(i), std::sqrt(w_ms(i)), 0.05 * std::sqrt(w_ms(i)))
        << "w " << i + 1;
  }
  // The weak direction is the least certain one: the product's point (SPEC §3).
  EXPECT_GT(u.input_angle_se_deg(3), u.input_angle_se_deg(0));
}

TEST(GainUncertainty, PrincipalMinorsOfA2x2HaveTheirClosedFormsAndFlagAFlippableDeterminant) {
  // G = [a b; c d], rows independent with diagonal covariances: Var det = d²σa² + c²σb² +
  // b²σc² + a²σd² (∂det/∂a = d, ∂/∂b = −c, ∂/∂c = −b, ∂/∂d = a).
  Eigen::MatrixXd G(2, 2);
  G << 1.0, 0.9, 1.0, 1.0;  // det = 0.1: nearly collinear
  const double s = 0.05;
  const std::vector<Eigen::MatrixXd> cov(2, Eigen::MatrixXd::Identity(2, 2) * s * s);
  const GainUncertainty u = gain_uncertainty(G, cov);
  ASSERT_EQ(u.principal_minors.size(), 3U);
  EXPECT_EQ(u.principal_minors[0].rows, std::vector<int>{0});
  EXPECT_NEAR(u.principal_minors[0].value, 1.0, 1e-12);
  EXPECT_NEAR(u.principal_minors[0].std_error, s, 1e-8);
  EXPECT_FALSE(u.principal_minors[0].sign_uncertain);
  const PrincipalMinor& det = u.principal_minors[2];
  EXPECT_EQ(det.rows, (std::vector<int>{0, 1}));
  EXPECT_NEAR(det.value, 0.1, 1e-12);
  EXPECT_NEAR(det.std_error, s * std::sqrt(1.0 + 1.0 + 0.81 + 1.0), 1e-8);
  EXPECT_TRUE(det.sign_uncertain);  // 0.1 < 1.96 · 0.098
  EXPECT_EQ(u.sign_uncertain_minors, 1);
}

TEST(GainUncertainty, RefusesACovarianceWithANaN) {
  Eigen::MatrixXd G = Eigen::MatrixXd::Identity(2, 2);
  std::vector<Eigen::MatrixXd> cov(2, Eigen::MatrixXd::Identity(2, 2));
  cov[1](0, 0) = std::nan("");
  EXPECT_THROW(gain_uncertainty(G, cov), std::invalid_argument);
}

// A white residual passes both tests at about their 1 % level, whatever the input's colour:
// a PRBS-like input held 16 samples is strongly autocorrelated (the independence test uses
// its Toeplitz autocorrelation, not ±2.58/√N lag by lag).
TEST(LongRunCovariance, TheWhitenedLagsAreNeweyAndWestsRuleAndSeeAShortCorrelation) {
  // ⌊4 (N/100)^(2/9)⌋, at least one lag.
  EXPECT_EQ(whitened_long_run_lags(4410), 9);
  EXPECT_EQ(whitened_long_run_lags(2000), 7);
  EXPECT_EQ(whitened_long_run_lags(100), 4);
  EXPECT_EQ(whitened_long_run_lags(1), 1);
  // An MA(1) score g_k = e_k + 0.5·e_{k−1}: its long-run variance is 1.5² = 2.25 per row,
  // where its variance alone is 1.25. Bartlett over 9 lags expects 1.25 + 2·0.9·0.5 = 2.15.
  constexpr Eigen::Index kN = 4000;
  std::mt19937_64 g(11);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd score(kN, 1);
  double before = normal(g);
  for (Eigen::Index k = 0; k < kN; ++k) {
    const double e = normal(g);
    score(k, 0) = e + 0.5 * before;
    before = e;
  }
  const double omega = long_run_covariance(score, whitened_long_run_lags(kN))(0, 0) / kN;
  const double variance = long_run_covariance(score, 0)(0, 0) / kN;
  EXPECT_NEAR(omega, 2.15, 0.15 * 2.15);
  EXPECT_NEAR(variance, 1.25, 0.1 * 1.25);
}

TEST(ResidualTests, AWhiteResidualPassesAtAboutTheStatedLevelWithAHeldBinaryInput) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> z(0.0, 1.0);
  std::bernoulli_distribution coin(0.5);
  constexpr int kTrials = 400, kN = 2000;
  int not_white = 0, dependent = 0;
  for (int t = 0; t < kTrials; ++t) {
    Eigen::VectorXd e(kN);
    Eigen::MatrixXd U(kN, 1);
    double level = 1.0;
    for (int k = 0; k < kN; ++k) {
      if (k % 16 == 0) level = coin(rng) ? 1.0 : -1.0;
      U(k, 0) = level;
      e(k) = z(rng);
    }
    const ResidualTests r = residual_tests(e, U);
    not_white += r.white() ? 0 : 1;
    dependent += r.independent_of(0) ? 0 : 1;
  }
  EXPECT_LE(not_white, kTrials * 3 / 100) << not_white << " of " << kTrials;
  EXPECT_LE(dependent, kTrials * 3 / 100) << dependent << " of " << kTrials;
}

TEST(ResidualTests, ACorrelatedResidualAndAMissedInputResponseAreCaught) {
  std::mt19937_64 rng(6);
  std::normal_distribution<double> z(0.0, 1.0);
  constexpr int kN = 2000;
  Eigen::VectorXd white(kN), coloured(kN), missed(kN);
  Eigen::MatrixXd U(kN, 1);
  double ar = 0.0, lagged = 0.0;
  for (int k = 0; k < kN; ++k) {
    U(k, 0) = z(rng);
    white(k) = z(rng);
    ar = 0.8 * ar + white(k);
    coloured(k) = ar;
    missed(k) = white(k) + 0.3 * lagged;  // 0.3 of the input one sample ago left unexplained
    lagged = U(k, 0);
  }
  EXPECT_FALSE(residual_tests(coloured, U).white());
  EXPECT_TRUE(residual_tests(missed, U).white());  // white enough: the input is white
  EXPECT_FALSE(residual_tests(missed, U).independent_of(0));
  EXPECT_TRUE(residual_tests(white, U).independent_of(0));
}

ElementEstimate estimated(double gain, double se) {
  ElementEstimate e;
  e.value = {gain, 1.0, 10.0, 2.0};
  e.std_error = {se, 0.1, 0.5, 0.5};
  return e;
}

ResidualTests passing(int inputs) {
  ResidualTests t;
  t.lags = 25;
  t.whiteness_limit = 44.3;
  t.independence_limit = 45.6;
  t.independence = Eigen::VectorXd::Zero(inputs);
  return t;
}

TEST(Grade, TheGainsRelativeIntervalSetsTheGradeAndEachFailedTestLowersIt) {
  ElementEstimate a = estimated(10.0, 0.5), b = estimated(10.0, 2.0), c = estimated(10.0, 4.0),
                  d = estimated(10.0, 6.0);  // 95 % half-widths 9.8 %, 39 %, 78 %, 118 %
  grade_row({&a, &b, &c, &d}, passing(4));
  EXPECT_EQ(a.grade, Grade::A);
  EXPECT_EQ(a.grade_reason, "");
  EXPECT_EQ(b.grade, Grade::B);
  EXPECT_EQ(c.grade, Grade::C);
  EXPECT_EQ(d.grade, Grade::D);
  EXPECT_NE(b.grade_reason.find("gain known to ±39 %"), std::string::npos) << b.grade_reason;

  ResidualTests failing = passing(2);
  failing.whiteness = 100.0;        // the row's residual is coloured
  failing.independence(1) = 100.0;  // and correlated with input 2
  ElementEstimate x = estimated(10.0, 0.5), y = estimated(10.0, 0.5);
  grade_row({&x, &y}, failing);
  EXPECT_EQ(x.grade, Grade::B);  // whiteness only
  EXPECT_EQ(y.grade, Grade::C);  // whiteness and its own input
  EXPECT_NE(y.grade_reason.find("residual correlated with this input"), std::string::npos);
}

TEST(Grade, AnUpperBoundCapsTheGradeAtCAndANotEstimatedElementIsD) {
  ElementEstimate bound = estimated(10.0, 0.1);
  bound.value.tau1_min = 150.0;
  bound.at_bound[kTp1] = Bound::upper;
  ElementEstimate zero_tp2 = estimated(10.0, 0.1);  // T_p2 on its lower bound 0: first order
  zero_tp2.value.tau2_min = 0.0;
  zero_tp2.at_bound[kTp2] = Bound::lower;
  ElementEstimate none;
  none.status = ElementStatus::input_not_moved;
  grade_row({&bound, &zero_tp2, &none}, passing(3));
  EXPECT_EQ(bound.grade, Grade::C);
  EXPECT_NE(bound.grade_reason.find("Tp1 = 150 (upper bound)"), std::string::npos);
  EXPECT_EQ(zero_tp2.grade, Grade::A);
  EXPECT_EQ(none.grade, Grade::D);
}

}  // namespace
}  // namespace excite::host
