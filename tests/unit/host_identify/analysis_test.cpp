// SPDX-License-Identifier: MIT
// Gain analysis, balance and the bounded Levenberg–Marquardt, checked by hand-computed cases.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "host/identify/balance.hpp"
#include "host/identify/bounded_lm.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {
namespace {

TEST(GainAnalysis, DiagonalGainHasKnownSvdXiAndRga) {
  Eigen::MatrixXd G(2, 2);
  G << 10.0, 0.0, 0.0, -0.5;
  const GainAnalysis a = analyse_gain(G);
  EXPECT_NEAR(a.singular_values(0), 10.0, 1e-12);
  EXPECT_NEAR(a.singular_values(1), 0.5, 1e-12);
  EXPECT_NEAR(a.xi(1), 20.0, 1e-12);
  EXPECT_NEAR(a.condition_number, 20.0, 1e-12);
  EXPECT_TRUE(a.rga.isApprox(Eigen::MatrixXd::Identity(2, 2), 1e-12));
}

// Wood–Berry G(0) = [12.8 −18.9; 6.6 −19.4]: λ11 = 1/(1 − g12 g21/(g11 g22)) = 2.0094, and
// SPEC §7 gives σ = 30.40, 4.064.
TEST(GainAnalysis, WoodBerryRgaAndSingularValues) {
  Eigen::MatrixXd G(2, 2);
  G << 12.8, -18.9, 6.6, -19.4;
  const GainAnalysis a = analyse_gain(G);
  const double l11 = 1.0 / (1.0 - (-18.9 * 6.6) / (12.8 * -19.4));
  EXPECT_NEAR(a.rga(0, 0), l11, 1e-12);
  EXPECT_NEAR(a.rga(0, 1), 1.0 - l11, 1e-12);
  EXPECT_NEAR(a.rga.row(1).sum(), 1.0, 1e-12);
  EXPECT_NEAR(a.singular_values(0), 30.40, 0.005);
  EXPECT_NEAR(a.singular_values(1), 4.064, 0.0005);
}

TEST(GainAnalysis, SingularGainHasInfiniteConditionAndNoRga) {
  Eigen::MatrixXd G(2, 2);
  G << 1.0, 2.0, 2.0, 4.0;
  const GainAnalysis a = analyse_gain(G);
  EXPECT_TRUE(std::isinf(a.condition_number) || a.condition_number > 1e15);
  EXPECT_TRUE(a.rga.array().isNaN().all());
}

Eigen::MatrixXd gaussian(Eigen::Index N, Eigen::Index p, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::MatrixXd Y(N, p);
  for (Eigen::Index c = 0; c < p; ++c) {
    for (Eigen::Index r = 0; r < N; ++r) Y(r, c) = n01(rng);
  }
  return Y;
}

// Outputs exactly along w_1: the projection on w_2 is zero, so the ratio is 0; and the two
// outputs are perfectly correlated, so Υ = 0.
TEST(Balance, OutputsAlongOneDirectionGiveRatioZero) {
  Eigen::MatrixXd W(2, 2);
  W << 1.0, -1.0, 1.0, 1.0;
  W /= std::sqrt(2.0);
  const Eigen::VectorXd s = gaussian(500, 1, 3).col(0);
  const Eigen::MatrixXd Y = s * W.col(0).transpose();
  const DirectionalBalance b = directional_balance(Y, W);
  EXPECT_NEAR(b.std_dev(1), 0.0, 1e-12);
  EXPECT_NEAR(b.ratio, 0.0, 1e-12);
  EXPECT_NEAR(b.projections(7, 0), s(7), 1e-12);
  EXPECT_NEAR(output_correlation_determinant(Y), 0.0, 1e-12);
}

// Hand example: y(k) = [1, 0], [−1, 0], [0, 2], [0, −2] with W = I: std of the projections
// are √(2/3) and √(8/3), ratio 1/2; the outputs are uncorrelated, Υ = 1.
TEST(Balance, HandComputedFourSamples) {
  Eigen::MatrixXd Y(4, 2);
  Y << 1, 0, -1, 0, 0, 2, 0, -2;
  const DirectionalBalance b = directional_balance(Y, Eigen::MatrixXd::Identity(2, 2));
  EXPECT_NEAR(b.std_dev(0), std::sqrt(2.0 / 3.0), 1e-14);
  EXPECT_NEAR(b.std_dev(1), std::sqrt(8.0 / 3.0), 1e-14);
  EXPECT_NEAR(b.ratio, 0.5, 1e-14);
  EXPECT_NEAR(output_correlation_determinant(Y), 1.0, 1e-14);
}

// Independent equal-variance outputs with W = I: ratio ≈ 1 and Υ ≈ 1 (sampling error
// ~1/√N with N = 20000).
TEST(Balance, IndependentEqualVarianceOutputsAreBalanced) {
  const Eigen::MatrixXd Y = gaussian(20000, 3, 5);
  const DirectionalBalance b = directional_balance(Y, Eigen::MatrixXd::Identity(3, 3));
  EXPECT_NEAR(b.ratio, 1.0, 0.03);
  EXPECT_NEAR(output_correlation_determinant(Y), 1.0, 0.01);
}

// Correlation ρ between two outputs: Υ = 1 − ρ².
TEST(Balance, UpsilonOfTwoCorrelatedOutputs) {
  Eigen::MatrixXd Y(4, 2);
  Y << 1, 1, -1, -1, 1, -1, -1, 1;  // ρ = 0
  Y(0, 1) = 2.0;                    // breaks the symmetry: compute ρ directly
  const Eigen::MatrixXd C = Y.rowwise() - Y.colwise().mean();
  const double rho = C.col(0).dot(C.col(1)) / (C.col(0).norm() * C.col(1).norm());
  EXPECT_NEAR(output_correlation_determinant(Y), 1.0 - rho * rho, 1e-14);
}

TEST(Balance, BadInputIsExplained) {
  const Eigen::MatrixXd Y = gaussian(10, 2, 1);
  EXPECT_THROW(directional_balance(Y, Eigen::MatrixXd::Identity(3, 3)), std::invalid_argument);
  Eigen::MatrixXd flat = Y;
  flat.col(1).setConstant(4.0);
  try {
    output_correlation_determinant(flat);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("output 2 is constant"), std::string::npos);
  }
}

// min (x0 − 3)² + (x1 + 1)² with x0 ≤ 2, x1 ≥ 0: the solution (2, 0) lies on both bounds.
TEST(BoundedLm, StopsOnTheBoundsOfABoxConstrainedQuadratic) {
  LmProblem p;
  p.residual = [](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r.resize(2);
    r << 3.0 - x(0), -1.0 - x(1);
    return true;
  };
  p.jacobian = [](const Eigen::VectorXd&, Eigen::MatrixXd& J) {
    J = Eigen::MatrixXd::Identity(2, 2);
  };
  p.lower = Eigen::Vector2d(-10.0, 0.0);
  p.upper = Eigen::Vector2d(2.0, 10.0);
  p.scale = Eigen::Vector2d(1.0, 1.0);
  const LmResult r = minimise_bounded(p, Eigen::Vector2d(0.5, 5.0), LmOptions{});
  EXPECT_TRUE(r.converged);
  EXPECT_DOUBLE_EQ(r.x(0), 2.0);
  EXPECT_DOUBLE_EQ(r.x(1), 0.0);
  EXPECT_NEAR(r.cost, 2.0, 1e-12);
}

// Rosenbrock as least squares, unconstrained: converges to (1, 1).
TEST(BoundedLm, SolvesRosenbrock) {
  LmProblem p;
  p.residual = [](const Eigen::VectorXd& x, Eigen::VectorXd& r) {
    r.resize(2);
    r << 10.0 * (x(1) - x(0) * x(0)), 1.0 - x(0);
    r = -r;  // r = y − f with y = 0
    return true;
  };
  p.jacobian = [](const Eigen::VectorXd& x, Eigen::MatrixXd& J) {
    J.resize(2, 2);
    J << -20.0 * x(0), 10.0, -1.0, 0.0;
  };
  const double inf = std::numeric_limits<double>::infinity();
  p.lower = Eigen::Vector2d(-inf, -inf);
  p.upper = Eigen::Vector2d(inf, inf);
  p.scale = Eigen::Vector2d(1.0, 1.0);
  const LmResult r = minimise_bounded(p, Eigen::Vector2d(-1.2, 1.0), LmOptions{});
  EXPECT_NEAR(r.x(0), 1.0, 1e-8);
  EXPECT_NEAR(r.x(1), 1.0, 1e-8);
}

}  // namespace
}  // namespace excite::host
