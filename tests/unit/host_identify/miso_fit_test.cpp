// SPDX-License-Identifier: MIT
// fit_miso's shortcuts (issue 44) change nothing it returns: a trial fit without standard
// errors (MisoUncertainty::none) ends at the same estimates and simulation, bit for bit, as
// the full fit; and the simulation it returns is the one of its estimates (kept from the
// minimiser's last accepted step, not simulated again), on a layout with unscored rows and two
// segments as on one whole run.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "host/identify/miso_fit.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

struct Row {
  Eigen::MatrixXd U;
  Eigen::VectorXd y;
  std::vector<ElementModel> truth;
};

// Two inputs, one two-pole element and one underdamped element with a lag and a zero, noise.
Row noisy_row() {
  Row r;
  r.U = testing::prbs_inputs(2, 9, 3, 100, 1500, 1.0);
  ElementModel b = with_structure(ElementModel{}, Structure::underdamped_lag_zero);
  b.gain = -2.0;
  b.delay_min = 1.4;
  b.tau1_min = 12.0;
  b.zero_min = 4.0;
  b.natural_min = 4.2;
  b.damping = 0.35;
  r.truth = {ElementModel{3.0, 2.3, 20.0, 5.0}, b};
  Eigen::MatrixXd Y = testing::plant_outputs(r.truth, 1, 2, 1.0, r.U);
  testing::add_noise(Y, 1e-3, 7);
  r.y = Y.col(0);
  return r;
}

// Rows 600–649 not scored, a new segment from row 900.
SampleLayout flagged_layout(Eigen::Index N) {
  SampleLayout l = SampleLayout::whole(N);
  l.weight.segment(600, 50).setZero();
  l.segments = {Segment{0, 900}, Segment{900, N}};
  return l;
}

// A start away from the truth, so the fit takes several steps.
std::vector<ElementModel> start_of(const std::vector<ElementModel>& truth) {
  std::vector<ElementModel> s = truth;
  for (ElementModel& g : s) {
    g.gain *= 0.7;
    g.delay_min *= 0.5;
    g.tau1_min *= 1.5;
  }
  return s;
}

Eigen::VectorXd simulated(const Eigen::MatrixXd& U, const std::vector<ElementModel>& elements,
                          const SampleLayout& layout) {
  Eigen::VectorXd y_hat = Eigen::VectorXd::Zero(U.rows());
  Eigen::VectorXd z(U.rows());
  for (std::size_t e = 0; e < elements.size(); ++e) {
    ElementModel unit = elements[e];
    unit.gain = 1.0;
    const auto u = U.col(static_cast<Eigen::Index>(e));
    simulate_segments(discretise(unit, 1.0), {u.data(), static_cast<std::size_t>(u.size())},
                      {z.data(), static_cast<std::size_t>(z.size())}, layout.segments);
    y_hat += elements[e].gain * z;
  }
  return y_hat;
}

void expect_same_fit(const SampleLayout& layout) {
  const Row r = noisy_row();
  const MisoBounds bounds{20.0, 150.0, natural_period_floor(1.0)};
  const Eigen::MatrixXd no_trend(r.U.rows(), 0);
  const MisoResult full =
      fit_miso(r.U, r.y, {0, 1}, start_of(r.truth), 1.0, bounds, 200, layout, no_trend);
  const MisoResult trial = fit_miso(r.U, r.y, {0, 1}, start_of(r.truth), 1.0, bounds, 200, layout,
                                    no_trend, LmOptions{}.cost_tolerance, MisoUncertainty::none);
  ASSERT_GT(full.iterations, 3);
  EXPECT_EQ(trial.iterations, full.iterations);
  std::vector<ElementModel> ends;
  for (std::size_t e = 0; e < 2; ++e) {
    const ElementEstimate& a = full.elements[e];
    const ElementEstimate& b = trial.elements[e];
    for (int p = 0; p < kParameters; ++p) EXPECT_EQ(a.value[p], b.value[p]) << e << " " << p;
    EXPECT_TRUE(std::isfinite(a.std_error.gain));
    EXPECT_TRUE(std::isnan(b.std_error.gain));
    EXPECT_EQ(a.at_bound, b.at_bound);
    ends.push_back(a.value);
  }
  EXPECT_EQ(full.y_hat, trial.y_hat);  // bit for bit
  // The returned simulation is the estimates' own (T_p1 and T_p2 are symmetric).
  const Eigen::VectorXd fresh = simulated(r.U, ends, layout);
  EXPECT_LE((full.y_hat - fresh).cwiseAbs().maxCoeff(), 1e-12 * fresh.cwiseAbs().maxCoeff());
  // And the fit found the truth's basin: gains within 5 %.
  EXPECT_NEAR(ends[0].gain, 3.0, 0.15);
  EXPECT_NEAR(ends[1].gain, -2.0, 0.10);
}

TEST(MisoFit, WithoutStandardErrorsTheSameEstimatesAndSimulationOnAWholeRun) {
  expect_same_fit(SampleLayout::whole(1500));
}

TEST(MisoFit, WithoutStandardErrorsTheSameEstimatesAndSimulationWithUnscoredRowsAndSegments) {
  expect_same_fit(flagged_layout(1500));
}

}  // namespace
}  // namespace excite::host
