// SPDX-License-Identifier: MIT
#include "host/identify/validate.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "test_data.hpp"

namespace excite::host {
namespace {

// (5.5.1) by hand: y = (1, 2, 3), ŷ = (1, 2, 4): ‖ŷ − y‖ = 1, ‖y − ȳ‖ = √2.
TEST(FitPercent, HandComputed) {
  const Eigen::Vector3d y(1.0, 2.0, 3.0);
  EXPECT_NEAR(fit_percent(y, Eigen::Vector3d(1.0, 2.0, 4.0)), 100.0 * (1.0 - 1.0 / std::sqrt(2.0)),
              1e-12);
  EXPECT_DOUBLE_EQ(fit_percent(y, y), 100.0);
  // Predicting the mean scores 0 %.
  EXPECT_NEAR(fit_percent(y, Eigen::Vector3d::Constant(2.0)), 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(fit_percent(Eigen::Vector3d::Ones(), y)));
  EXPECT_THROW(fit_percent(y, Eigen::Vector2d(1.0, 2.0)), std::invalid_argument);
}

IdentifiedModel model_of(const std::vector<ElementModel>& g, int p, int n, double gain_factor) {
  IdentifiedModel m;
  m.inputs = n;
  m.outputs = p;
  m.sample_time_min = 1.0;
  for (ElementModel e : g) {
    e.gain *= gain_factor;
    ElementEstimate est;
    est.value = e;
    m.elements.push_back(est);
  }
  return m;
}

const std::vector<ElementModel> kTruth = {
    {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};

TEST(Fit, TrueModelOnOtherDataFitsPerfectly) {
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 7, 5, 40, 600, 2.0);
  const Eigen::MatrixXd Y = testing::plant_outputs(kTruth, 2, 2, 1.0, U);
  const std::vector<double> f = fit(model_of(kTruth, 2, 2, 1.0), U, Y);
  ASSERT_EQ(f.size(), 2U);
  EXPECT_GT(f[0], 100.0 - 1e-8);
  EXPECT_GT(f[1], 100.0 - 1e-8);
  // Gains 10 % high: ‖ŷ − y‖ = 0.1 ‖y‖, so the fit is 100 (1 − 0.1 ‖y‖/‖y − ȳ‖).
  const std::vector<double> g = fit(model_of(kTruth, 2, 2, 1.1), U, Y);
  const Eigen::VectorXd y0 = Y.col(0);
  const double expected =
      100.0 * (1.0 - 0.1 * y0.norm() / (y0.array() - y0.mean()).matrix().norm());
  EXPECT_NEAR(g[0], expected, 1e-9);
}

TEST(Fit, UnestimatedElementGivesNanOnlyWhereItsInputMoves) {
  IdentifiedModel m = model_of(kTruth, 2, 2, 1.0);
  m.element(1, 1).status = ElementStatus::input_not_moved;
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 7, 5, 40, 600, 2.0);
  const Eigen::MatrixXd Y = testing::plant_outputs(kTruth, 2, 2, 1.0, U);
  const std::vector<double> f = fit(m, U, Y);
  EXPECT_GT(f[0], 99.99);
  EXPECT_TRUE(std::isnan(f[1]));
}

TEST(Fit, SizeMismatchIsNamed) {
  const Eigen::MatrixXd U = Eigen::MatrixXd::Ones(10, 3);
  try {
    fit(model_of(kTruth, 2, 2, 1.0), U, Eigen::MatrixXd::Ones(10, 2));
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("U 10×3"), std::string::npos) << e.what();
  }
}

// Three runs, three models (true gains, +10 %, −50 %): every entry is the mean over outputs
// of fit(), and the summaries pick the right runs.
TEST(CrossValidate, TableAndSummariesFollowTheFits) {
  std::vector<Dataset> data;
  for (int r = 0; r < 3; ++r) {
    Dataset d;
    d.name = "run" + std::to_string(r);
    d.U = testing::prbs_inputs(2, 7, 3 + 2 * r, 20 + 10 * r, 500, 1.0 + r);
    d.Y = testing::plant_outputs(kTruth, 2, 2, 1.0, d.U);
    data.push_back(d);
  }
  const std::vector<IdentifiedModel> models = {
      model_of(kTruth, 2, 2, 1.0), model_of(kTruth, 2, 2, 1.1), model_of(kTruth, 2, 2, 0.5)};
  const CrossValidation cv = cross_validate(models, data);
  ASSERT_EQ(cv.fit.rows(), 3);
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const std::vector<double> f =
          fit(models[static_cast<std::size_t>(a)], data[static_cast<std::size_t>(b)].U,
              data[static_cast<std::size_t>(b)].Y);
      EXPECT_DOUBLE_EQ(cv.fit(a, b), (f[0] + f[1]) / 2.0);
    }
  }
  const auto& m1 = cv.models[1];
  EXPECT_DOUBLE_EQ(m1.own, cv.fit(1, 1));
  EXPECT_DOUBLE_EQ(m1.cross_average, (cv.fit(1, 0) + cv.fit(1, 2)) / 2.0);
  EXPECT_DOUBLE_EQ(m1.cross_best, std::max(cv.fit(1, 0), cv.fit(1, 2)));
  EXPECT_DOUBLE_EQ(m1.cross_worst, std::min(cv.fit(1, 0), cv.fit(1, 2)));
  EXPECT_NE(m1.best_on, m1.worst_on);
  EXPECT_GT(cv.models[0].cross_average, 99.99);
  EXPECT_LT(cv.models[2].cross_average, cv.models[1].cross_average);
  EXPECT_THROW(cross_validate({models[0]}, {data[0]}), std::invalid_argument);
}

}  // namespace
}  // namespace excite::host
