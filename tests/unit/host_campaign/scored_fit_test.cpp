// SPDX-License-Identifier: MIT
// The truth's fit and a model's loss against it (issue 45) on a case worked out by hand:
// a static plant y = 2u, a model y = 1.5u, inputs u = 1, 1, −1, −1, … and noise
// a·(1, −1, 1, −1, …), orthogonal to u, both of zero mean over every 4 samples. Then
// ‖y − ȳ‖² = N(4 + a²), the truth's error is the noise (‖·‖² = N a²) and the model's is
// 0.5u + noise (‖·‖² = N(0.25 + a²)), so by (5.5.1)
//   truth fit = 100 (1 − a/√(4 + a²)),   model fit = 100 (1 − √(0.25 + a²)/√(4 + a²)):
//   a = 0.5: 75.746 and 65.700, loss 10.046 points;  a = 1: 55.279 and 50.000, loss 5.279.
// The noisier run gives the worst cross-fit; the model loses more on the quieter one.

#include "host/campaign/scored_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "host/measures/cross_fit.hpp"
#include "sim/lti/transfer_matrix.hpp"

namespace excite::host {
namespace {

constexpr Eigen::Index kRows = 400;

Eigen::MatrixXd inputs() {
  Eigen::MatrixXd U(kRows, 1);
  for (Eigen::Index k = 0; k < kRows; ++k) U(k, 0) = (k % 4) < 2 ? 1.0 : -1.0;
  return U;
}

// y = 2u + a·(±1 alternating).
Eigen::MatrixXd outputs(double noise) {
  const Eigen::MatrixXd U = inputs();
  Eigen::MatrixXd Y(kRows, 1);
  for (Eigen::Index k = 0; k < kRows; ++k) Y(k, 0) = 2.0 * U(k, 0) + (k % 2 ? -noise : noise);
  return Y;
}

IdentifiedModel static_model(double gain) {
  IdentifiedModel m;
  m.inputs = 1;
  m.outputs = 1;
  m.sample_time_min = 1.0;
  ElementEstimate e;
  e.value.gain = gain;  // two poles at T = 0: a static gain
  m.elements.push_back(e);
  return m;
}

std::unique_ptr<sim::Plant> static_plant() {
  return sim::make_linear_plant("static", sim::TransferMatrix::parse({{"2"}}));
}

double truth_by_hand(double a) {
  return 100.0 * (1.0 - a / std::sqrt(4.0 + a * a));
}
double model_by_hand(double a) {
  return 100.0 * (1.0 - std::sqrt(0.25 + a * a) / std::sqrt(4.0 + a * a));
}

TEST(TruthFit, TheTruePlantsFitIsTheBoundTheNoiseSets) {
  const auto plant = static_plant();
  for (const double a : {0.5, 1.0}) {
    const SampleLayout whole = SampleLayout::whole(kRows);
    const std::vector<double> truth = truth_fit(*plant, inputs(), outputs(a), 1.0, whole);
    const std::vector<double> model = scored_fit(static_model(1.5), inputs(), outputs(a), whole);
    ASSERT_EQ(truth.size(), 1U);
    EXPECT_NEAR(truth[0], truth_by_hand(a), 1e-9) << a;
    EXPECT_NEAR(model[0], model_by_hand(a), 1e-9) << a;
  }
  EXPECT_NEAR(truth_by_hand(0.5) - model_by_hand(0.5), 10.046, 5e-4);
  EXPECT_NEAR(truth_by_hand(1.0) - model_by_hand(1.0), 5.279, 5e-4);
}

// Rows a run's flags leave out count for neither the truth nor the model: two segments,
// each starting with four unscored rows of garbage (a whole period of both patterns).
TEST(TruthFit, ScoresOnlyTheRowsTheLayoutScores) {
  SampleLayout layout;
  layout.segments = {{0, kRows / 2}, {kRows / 2, kRows}};
  layout.weight = Eigen::VectorXd::Ones(kRows);
  Eigen::MatrixXd Y = outputs(0.5);
  for (const Eigen::Index start : {Eigen::Index{0}, kRows / 2}) {
    layout.weight.segment(start, 4).setZero();
    Y.middleRows(start, 4).setConstant(1e3);
  }
  layout.check();
  const auto plant = static_plant();
  EXPECT_NEAR(truth_fit(*plant, inputs(), Y, 1.0, layout)[0], truth_by_hand(0.5), 1e-9);
  EXPECT_NEAR(scored_fit(static_model(1.5), inputs(), Y, layout)[0], model_by_hand(0.5), 1e-9);
}

// The whole chain as the campaign runs it: the model (from its own run 2) on runs 0 (a = 0.5)
// and 1 (a = 1), each beside the truth's fit there.
TEST(TruthFit, LossAgainstTheTruthNamesTheQuieterRunTheWorstCrossFitTheNoisier) {
  const auto plant = static_plant();
  const SampleLayout whole = SampleLayout::whole(kRows);
  Eigen::VectorXd row(3), truth(3);
  const double noise[3] = {0.5, 1.0, 0.2};
  for (int b = 0; b < 3; ++b) {
    row(b) = scored_fit(static_model(1.5), inputs(), outputs(noise[b]), whole)[0];
    truth(b) = truth_fit(*plant, inputs(), outputs(noise[b]), 1.0, whole)[0];
  }
  const CrossFitFigures f = cross_fit_figures(row, truth, 2);
  EXPECT_NEAR(f.worst, 50.0, 1e-9);
  EXPECT_EQ(f.worst_on, 1);
  EXPECT_NEAR(f.truth_on_worst, truth_by_hand(1.0), 1e-9);
  EXPECT_NEAR(f.loss_worst, 10.046, 5e-4);
  EXPECT_EQ(f.loss_worst_on, 0);
  EXPECT_NEAR(f.loss_average, 0.5 * (10.046 + 5.279), 5e-4);
}

}  // namespace
}  // namespace excite::host
