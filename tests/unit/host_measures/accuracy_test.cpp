// SPDX-License-Identifier: MIT
// The accuracy criterion: principal minors' signs, σ_n within 20 %, v_n within 10°.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "host/measures/accuracy.hpp"

namespace mc = excite::host;
using excite::host::analyse_gain;

namespace {

// Wood–Berry's G(0) (SPEC §7: σ = 30.40, 4.064).
Eigen::MatrixXd wood_berry() {
  Eigen::MatrixXd g(2, 2);
  g << 12.8, -18.9, 6.6, -19.4;
  return g;
}

// G with its smallest singular value scaled by `factor` and v_n turned by `degrees`.
Eigen::MatrixXd perturbed(const Eigen::MatrixXd& g, double factor, double degrees) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(g, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::VectorXd s = svd.singularValues();
  s(1) *= factor;
  const double a = degrees * std::numbers::pi / 180.0;
  Eigen::Matrix2d turn;
  turn << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  const Eigen::MatrixXd V = turn * svd.matrixV();
  return svd.matrixU() * s.asDiagonal() * V.transpose();
}

}  // namespace

TEST(Accuracy, TheTrueGainMeetsItWithNoError) {
  const mc::TruePlant truth = mc::true_plant_of(wood_berry());
  const mc::Accuracy a = mc::judge(truth, analyse_gain(wood_berry()));
  EXPECT_TRUE(a.met);
  EXPECT_NEAR(a.sigma_n_error, 0.0, 1e-12);
  EXPECT_NEAR(a.weakest_angle_deg, 0.0, 1e-5);
}

TEST(Accuracy, SigmaNOffByMoreThanTwentyPercentFails) {
  const mc::TruePlant truth = mc::true_plant_of(wood_berry());
  EXPECT_TRUE(mc::judge(truth, analyse_gain(perturbed(wood_berry(), 1.18, 0.0))).met);
  const mc::Accuracy a = mc::judge(truth, analyse_gain(perturbed(wood_berry(), 1.22, 0.0)));
  EXPECT_NEAR(a.sigma_n_error, 0.22, 1e-9);
  EXPECT_FALSE(a.met);
  EXPECT_FALSE(mc::judge(truth, analyse_gain(perturbed(wood_berry(), 0.78, 0.0))).met);
}

TEST(Accuracy, WeakestDirectionTurnedByMoreThanTenDegreesFails) {
  const mc::TruePlant truth = mc::true_plant_of(wood_berry());
  const mc::Accuracy ok = mc::judge(truth, analyse_gain(perturbed(wood_berry(), 1.0, 8.0)));
  EXPECT_NEAR(ok.weakest_angle_deg, 8.0, 1e-6);
  EXPECT_TRUE(ok.met);
  const mc::Accuracy bad = mc::judge(truth, analyse_gain(perturbed(wood_berry(), 1.0, 12.0)));
  EXPECT_NEAR(bad.weakest_angle_deg, 12.0, 1e-6);
  EXPECT_FALSE(bad.met);
}

TEST(Accuracy, AWrongSignOfAPrincipalMinorFails) {
  const mc::TruePlant truth = mc::true_plant_of(wood_berry());
  ASSERT_EQ(truth.minors.size(), 3U);  // g11, g22, det
  Eigen::MatrixXd g = wood_berry();
  g(0, 0) = -0.01;  // g11's sign flipped; σ_n and v_n change too, the minors decide first
  const mc::Accuracy a = mc::judge(truth, analyse_gain(g));
  EXPECT_FALSE(a.minor_signs_right);
  EXPECT_FALSE(a.met);
}

TEST(Accuracy, NoIdentifiedGainIsNotMet) {
  const mc::Accuracy a = mc::judge(mc::true_plant_of(wood_berry()), std::nullopt);
  EXPECT_FALSE(a.gain_identified);
  EXPECT_FALSE(a.met);
  EXPECT_TRUE(std::isnan(a.sigma_n_error));
}

TEST(Accuracy, PrincipalMinorsAreOrderedByBitMask) {
  const std::vector<double> m = mc::principal_minor_values(wood_berry());
  ASSERT_EQ(m.size(), 3U);
  EXPECT_DOUBLE_EQ(m[0], 12.8);
  EXPECT_DOUBLE_EQ(m[1], -19.4);
  EXPECT_NEAR(m[2], 12.8 * -19.4 - (-18.9 * 6.6), 1e-12);
}
