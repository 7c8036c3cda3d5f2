// SPDX-License-Identifier: MIT
// One model's cross-fit figures and its loss against the truth (issue 45), on numbers whose
// answer is worked out by hand.
#include "host/measures/cross_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::host {
namespace {

// GIVEN model 1 of three runs, its own fit 99 on run 1 (ignored), 80 % on run 0 and 60 % on
// run 2; the true plant fits run 0 to 90 % and the noisy run 2 to 62 %.
// THEN the worst cross-fit is run 2's 60 %, where the truth reaches only 62 %; but the
// model loses most on run 0: 90 − 80 = 10 points (run 2: 2), average (10 + 2)/2 = 6.
TEST(CrossFitFigures, LossAgainstTheTruthIsTheTruthsFitLessTheCrossFit) {
  const Eigen::Vector3d fit(80.0, 99.0, 60.0);
  const Eigen::Vector3d truth(90.0, 97.0, 62.0);
  const CrossFitFigures f = cross_fit_figures(fit, truth, 1);
  EXPECT_EQ(f.average, 70.0);
  EXPECT_EQ(f.best, 80.0);
  EXPECT_EQ(f.best_on, 0);
  EXPECT_EQ(f.worst, 60.0);
  EXPECT_EQ(f.worst_on, 2);
  EXPECT_EQ(f.truth_on_worst, 62.0);
  EXPECT_EQ(f.loss_average, 6.0);
  EXPECT_EQ(f.loss_worst, 10.0);
  EXPECT_EQ(f.loss_worst_on, 0);
}

// Without a truth (measured data) the cross-fit figures and the bounding run are there, the
// loss is not.
TEST(CrossFitFigures, WithoutTruthNamesTheRunThatBoundsTheWorstCrossFit) {
  const Eigen::Vector3d fit(80.0, 99.0, 60.0);
  const CrossFitFigures f = cross_fit_figures(fit, Eigen::VectorXd(), 1);
  EXPECT_EQ(f.worst, 60.0);
  EXPECT_EQ(f.worst_on, 2);
  EXPECT_TRUE(std::isnan(f.truth_on_worst));
  EXPECT_TRUE(std::isnan(f.loss_average));
  EXPECT_TRUE(std::isnan(f.loss_worst));
  EXPECT_EQ(f.loss_worst_on, -1);
}

// A model that cannot predict one run has no cross-fit (as cross_validate); a run whose
// truth is unknown leaves the loss unknown but not the cross-fit.
TEST(CrossFitFigures, NaNFitOrTruthPropagates) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CrossFitFigures no_fit =
      cross_fit_figures(Eigen::Vector3d(80.0, 99.0, nan), Eigen::Vector3d(90.0, 97.0, 62.0), 1);
  EXPECT_TRUE(std::isnan(no_fit.average));
  EXPECT_TRUE(std::isnan(no_fit.worst));
  EXPECT_EQ(no_fit.worst_on, -1);
  EXPECT_TRUE(std::isnan(no_fit.loss_average));
  // The own run's NaN counts for nothing.
  const CrossFitFigures own_nan =
      cross_fit_figures(Eigen::Vector3d(80.0, nan, 60.0), Eigen::Vector3d(90.0, nan, 62.0), 1);
  EXPECT_EQ(own_nan.loss_average, 6.0);
  const CrossFitFigures no_truth =
      cross_fit_figures(Eigen::Vector3d(80.0, 99.0, 60.0), Eigen::Vector3d(90.0, 97.0, nan), 1);
  EXPECT_EQ(no_truth.average, 70.0);
  EXPECT_TRUE(std::isnan(no_truth.loss_average));
  EXPECT_TRUE(std::isnan(no_truth.loss_worst));
}

TEST(CrossFitFigures, RefusesSizesThatDoNotMatch) {
  const Eigen::Vector3d fit(80.0, 99.0, 60.0);
  EXPECT_THROW((void)cross_fit_figures(fit, Eigen::Vector2d(1.0, 2.0), 1), std::invalid_argument);
  EXPECT_THROW((void)cross_fit_figures(fit, Eigen::VectorXd(), 3), std::invalid_argument);
  EXPECT_THROW((void)cross_fit_figures(Eigen::VectorXd::Constant(1, 50.0), Eigen::VectorXd(), 0),
               std::invalid_argument);
  try {
    (void)cross_fit_figures(fit, Eigen::Vector2d(1.0, 2.0), 1);
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "cross-fit truth runs = 2, expected 0 (no truth) or 3");
  }
}

}  // namespace
}  // namespace excite::host
