// SPDX-License-Identifier: MIT
#include "host/identify/identify.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/identify/validate.hpp"
#include "tests/unit/host_identify/test_data.hpp"

namespace excite::host {
namespace {

using testing::plant_outputs;
using testing::prbs_inputs;

void expect_recovers(const IdentificationResult& r, const std::vector<TwoPoleDelay>& truth,
                     double rel) {
  const IdentifiedModel& m = r.model;
  for (int j = 0; j < m.outputs; ++j) {
    for (int i = 0; i < m.inputs; ++i) {
      const TwoPoleDelay t = truth[static_cast<std::size_t>(j * m.inputs + i)];
      const ElementEstimate& e = m.element(j, i);
      SCOPED_TRACE("element (" + std::to_string(j + 1) + "," + std::to_string(i + 1) + ")");
      EXPECT_EQ(e.status, ElementStatus::identified) << e.reason;
      EXPECT_NEAR(e.value.gain, t.gain, rel * std::abs(t.gain));
      EXPECT_NEAR(e.value.delay_min, t.delay_min, rel * std::max(t.delay_min, 1.0));
      EXPECT_NEAR(e.value.tp1_min, std::max(t.tp1_min, t.tp2_min), rel * t.tp1_min);
      EXPECT_NEAR(e.value.tp2_min, std::min(t.tp1_min, t.tp2_min), rel * t.tp2_min);
    }
  }
}

// GIVEN noise-free data of a 2×2 plant whose elements are exactly of form (6.1.1), with
// distinct time constants and fractional delays, under uncorrelated PRBS inputs
// WHEN identified THEN every parameter comes back to 1e-3 relative and the fit is ~100 %.
TEST(Identify, RecoversTrueParametersOfA2x2FromNoiseFreeData) {
  const std::vector<TwoPoleDelay> truth = {
      {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  const Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  const Eigen::MatrixXd Y = plant_outputs(truth, 2, 2, 1.0, U);
  const IdentificationResult r = identify(U, Y, 1.0);
  expect_recovers(r, truth, 1e-3);
  for (const OutputFit& f : r.fits) {
    EXPECT_GT(f.fit_percent, 99.99);
    EXPECT_TRUE(f.converged);
  }
  ASSERT_TRUE(r.gain.has_value());
  EXPECT_NEAR(r.gain->gain(1, 0), 0.8, 1e-3);
}

// The same on the 4×4 stripper-like plant over a 4080-sample experiment (SPEC §4 set-up:
// T = 1 min, T_sw = 16 min, n_r = 8, channels shifted by 16 switching intervals).
TEST(Identify, RecoversTrueParametersOfA4x4FromNoiseFreeData) {
  const std::vector<TwoPoleDelay> truth = testing::stripper_like_4x4();
  const Eigen::MatrixXd U = prbs_inputs(4, 8, 16, 16, 4080, 1.0);
  const Eigen::MatrixXd Y = plant_outputs(truth, 4, 4, 1.0, U);
  IdentifyOptions options;
  options.threads = 2;
  const IdentificationResult r = identify(U, Y, 1.0, options);
  expect_recovers(r, truth, 1e-3);
  ASSERT_TRUE(r.gain.has_value());
  // σ of the true G(0) from its gains (the B.0.5 gains: SPEC §7 gives κ = 125.2).
  Eigen::MatrixXd G0(4, 4);
  for (int k = 0; k < 16; ++k) G0(k / 4, k % 4) = truth[static_cast<std::size_t>(k)].gain;
  const Eigen::VectorXd s = G0.jacobiSvd().singularValues();
  EXPECT_NEAR(s(0), 20.470, 1e-3);
  EXPECT_NEAR(s(3), 0.1635, 1e-4);
  for (Eigen::Index i = 0; i < 4; ++i) {
    EXPECT_NEAR(r.gain->singular_values(i), s(i), 1e-3 * s(i));
  }
  EXPECT_NEAR(r.gain->condition_number, 125.2, 0.2);
}

}  // namespace
}  // namespace excite::host
