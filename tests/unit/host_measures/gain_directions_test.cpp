// SPDX-License-Identifier: MIT
#include "host/measures/gain_directions.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace excite::host {
namespace {

// G(0) of the 2×2 column (5.3.1): 87.8/(194s+1) ± 1.4/(15s+1) at s = 0.
Eigen::MatrixXd column2x2_gain() {
  Eigen::MatrixXd g(2, 2);
  g << 87.8, -87.8 + 1.4, 108.2, -108.2 - 1.4;
  return g;
}

TEST(AnalyseGain, ReproducesThePublishedSingularValuesAndRgaOfTheColumn) {
  const GainAnalysis a = analyse_gain(column2x2_gain());
  EXPECT_NEAR(a.singular_values(0), 197.21, 0.005);  // 5.3.2
  EXPECT_NEAR(a.singular_values(1), 1.3914, 0.00005);
  EXPECT_NEAR(a.condition_number, 141.73, 0.01);       // Table 5.2
  EXPECT_NEAR(a.rga(0, 0), 35.068, 0.001);             // Table 5.2
  EXPECT_NEAR(a.rga(0, 0) + a.rga(0, 1), 1.0, 1e-12);  // rows of the RGA sum to one
  EXPECT_NEAR(a.xi(1), a.condition_number, 1e-9);
}

TEST(AnalyseGain, DirectionInputGivesUnitOutputAlongItsOutputDirection) {
  Eigen::MatrixXd g(3, 3);
  g << 6, 20, -1, 8, 77, -5, 9, -37, -103;  // G(0) of the 3×3 column (B.0.4)
  const GainAnalysis a = analyse_gain(g);
  for (Eigen::Index i = 0; i < 3; ++i) {
    const Eigen::VectorXd u = a.input_directions.col(i) / a.singular_values(i);  // (5.2.2)
    const Eigen::VectorXd y = g * u;
    EXPECT_TRUE(y.isApprox(a.output_directions.col(i), 1e-12)) << "direction " << i;
    EXPECT_NEAR(y.norm(), 1.0, 1e-12);
  }
  EXPECT_NEAR(a.singular_values(0), 113.6, 0.05);  // SPEC §7
  EXPECT_NEAR(a.singular_values(2), 3.781, 0.0005);
}

TEST(AnalyseGain, SignConventionMakesLargestOutputComponentPositive) {
  const GainAnalysis a = analyse_gain(column2x2_gain());
  for (Eigen::Index i = 0; i < 2; ++i) {
    Eigen::Index largest = 0;
    a.output_directions.col(i).cwiseAbs().maxCoeff(&largest);
    EXPECT_GT(a.output_directions(largest, i), 0.0);
  }
}

TEST(AnalyseGain, WeakDirectionsAreThoseWithLargeXi) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(4, 4);
  g.diagonal() << 20.0, 16.0, 0.19, 0.16;  // two weak directions, as in 6.4.1
  const GainAnalysis a = analyse_gain(g);
  EXPECT_EQ(a.weak_directions(10.0), (std::vector<int>{2, 3}));
}

TEST(AnalyseGain, RequireFullRankRefusesASingularMatrixNamingIt) {
  Eigen::MatrixXd g(2, 2);
  g << 1, 2, 2, 4;
  const GainAnalysis a = analyse_gain(g);  // analysed: an identified G(0) may be singular
  EXPECT_TRUE(std::isinf(a.condition_number));
  EXPECT_TRUE(std::isnan(a.rga(0, 0)));
  try {
    require_full_rank(a);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("singular"), std::string::npos) << e.what();
  }
}

TEST(AnalyseGain, RefusesNonFiniteEntriesNamingTheIndex) {
  Eigen::MatrixXd g = Eigen::MatrixXd::Identity(2, 2);
  g(1, 0) = std::numeric_limits<double>::quiet_NaN();
  try {
    analyse_gain(g);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gain[1][0]"), std::string::npos) << e.what();
  }
}

TEST(StaticOutputExcursions, AreTheExtremesOfGTimesTheTable) {
  Eigen::MatrixXd g(2, 2);
  g << 1, 2, -1, 0.5;
  Eigen::MatrixXd table(3, 2);
  table << 1, 0, 0, 1, -1, -1;
  const auto ex = static_output_excursions(g, table);  // outputs: (1,−1), (2,0.5), (−3,0.5)
  ASSERT_EQ(ex.size(), 2U);
  EXPECT_DOUBLE_EQ(ex[0].min, -3.0);
  EXPECT_DOUBLE_EQ(ex[0].max, 2.0);
  EXPECT_DOUBLE_EQ(ex[1].min, -1.0);
  EXPECT_DOUBLE_EQ(ex[1].max, 0.5);
}

}  // namespace
}  // namespace excite::host
