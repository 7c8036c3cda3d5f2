// SPDX-License-Identifier: MIT
#include "host/identify/identify.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "host/identify/validate.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

using testing::plant_outputs;
using testing::prbs_inputs;

void expect_recovers(const IdentificationResult& r, const std::vector<ElementModel>& truth,
                     double rel) {
  const IdentifiedModel& m = r.model;
  for (int j = 0; j < m.outputs; ++j) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementModel t = truth[static_cast<std::size_t>(j * m.inputs + i)];
      const ElementEstimate& e = m.element(j, i);
      SCOPED_TRACE("element (" + std::to_string(j + 1) + "," + std::to_string(i + 1) + ")");
      EXPECT_EQ(e.status, ElementStatus::identified) << e.reason;
      EXPECT_NEAR(e.value.gain, t.gain, rel * std::abs(t.gain));
      EXPECT_NEAR(e.value.delay_min, t.delay_min, rel * std::max(t.delay_min, 1.0));
      EXPECT_NEAR(e.value.tau1_min, std::max(t.tau1_min, t.tau2_min), rel * t.tau1_min);
      EXPECT_NEAR(e.value.tau2_min, std::min(t.tau1_min, t.tau2_min), rel * t.tau2_min);
    }
  }
}

// GIVEN noise-free data of a 2×2 plant whose elements are exactly of form (6.1.1), with
// distinct time constants and fractional delays, under uncorrelated PRBS inputs
// WHEN identified THEN every parameter comes back to 1e-3 relative and the fit is ~100 %.
TEST(Identify, RecoversTrueParametersOfA2x2FromNoiseFreeData) {
  const std::vector<ElementModel> truth = {
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
  const std::vector<ElementModel> truth = testing::stripper_like_4x4();
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

// GIVEN a 2×2 experiment in which input 2 never moved
// THEN its elements are reported as not identifiable, with no parameters, the other
// elements are still recovered, and G(0) analysis says why it is unavailable.
TEST(Identify, ReportsAnInputThatNeverMovedInsteadOfInventingParameters) {
  const std::vector<ElementModel> truth = {
      {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  U.col(1).setZero();
  const Eigen::MatrixXd Y = plant_outputs(truth, 2, 2, 1.0, U);
  const IdentificationResult r = identify(U, Y, 1.0);
  for (int j = 0; j < 2; ++j) {
    const ElementEstimate& dead = r.model.element(j, 1);
    EXPECT_EQ(dead.status, ElementStatus::input_not_moved);
    EXPECT_FALSE(dead.estimated());
    EXPECT_TRUE(std::isnan(dead.value.gain));
    EXPECT_NE(dead.reason.find("never moved"), std::string::npos) << dead.reason;
    EXPECT_EQ(r.model.element(j, 0).status, ElementStatus::identified);
    EXPECT_NEAR(r.model.element(j, 0).value.gain, truth[static_cast<std::size_t>(2 * j)].gain,
                1e-3);
  }
  EXPECT_FALSE(r.gain.has_value());
  EXPECT_NE(r.gain_unavailable_reason.find("input_not_moved"), std::string::npos);
}

// Two inputs always moved together (e.g. only one gain direction excited) cannot be separated.
TEST(Identify, ReportsCollinearInputs) {
  const std::vector<ElementModel> truth = {
      {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  U.col(1) = -0.5 * U.col(0);
  const Eigen::MatrixXd Y = plant_outputs(truth, 2, 2, 1.0, U);
  const IdentificationResult r = identify(U, Y, 1.0);
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(r.model.element(0, i).status, ElementStatus::input_collinear);
    EXPECT_NE(r.model.element(0, i).reason.find("linear combination"), std::string::npos);
  }
}

// An element with a gain far below the noise is flagged weak rather than reported as known.
TEST(Identify, FlagsAGainHiddenInTheNoise) {
  const std::vector<ElementModel> truth = {
      {2.0, 1.3, 20.0, 5.0}, {1e-4, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  const Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  Eigen::MatrixXd Y = plant_outputs(truth, 2, 2, 1.0, U);
  testing::add_noise(Y, 0.03, 11);
  const IdentificationResult r = identify(U, Y, 1.0);
  EXPECT_EQ(r.model.element(0, 1).status, ElementStatus::weak_gain)
      << "K = " << r.model.element(0, 1).value.gain;
  EXPECT_NE(r.model.element(0, 1).reason.find("standard errors"), std::string::npos);
  EXPECT_EQ(r.model.element(0, 0).status, ElementStatus::identified);
  // With noise the estimates scatter by about their standard errors.
  const ElementEstimate& e = r.model.element(0, 0);
  EXPECT_NEAR(e.value.gain, 2.0, 5.0 * e.std_error.gain);
  EXPECT_GT(e.std_error.gain, 0.0);
}

TEST(Identify, OutputThatNeverMovedIsReported) {
  const Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 1008, 1.0);
  Eigen::MatrixXd Y = plant_outputs(
      {{2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}},
      2, 2, 1.0, U);
  Y.col(1).setConstant(0.0);
  const IdentificationResult r = identify(U, Y, 1.0);
  EXPECT_EQ(r.model.element(1, 0).status, ElementStatus::output_not_moved);
  EXPECT_TRUE(std::isnan(r.fits[1].fit_percent));
  EXPECT_EQ(r.model.element(0, 0).status, ElementStatus::identified);
}

std::string message_of(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T,
                       IdentifyOptions o = {}) {
  try {
    identify(U, Y, T, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Identify, BadInputGivesClearErrors) {
  const Eigen::MatrixXd U = prbs_inputs(2, 6, 8, 31, 500, 1.0);
  const Eigen::MatrixXd Y = Eigen::MatrixXd::Ones(500, 2);
  EXPECT_NE(message_of(U, Y.topRows(499), 1.0).find("U has 500 samples (rows) but Y has 499"),
            std::string::npos);
  Eigen::MatrixXd Ynan = Y;
  Ynan(17, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message_of(U, Ynan, 1.0).find("Y sample 17 (row), channel 2 is nan"), std::string::npos)
      << message_of(U, Ynan, 1.0);
  EXPECT_NE(message_of(U, Y, 0.0).find("sample time T_min = 0"), std::string::npos);
  // 2 inputs with delays up to 20 min at T = 1 min need 20 + 80 = 100 samples.
  EXPECT_EQ(minimum_samples(2, 1.0), 100);
  EXPECT_NE(message_of(U.topRows(99), Y.topRows(99), 1.0).find("expected at least 100"),
            std::string::npos)
      << message_of(U.topRows(99), Y.topRows(99), 1.0);
  IdentifyOptions o;
  o.max_delay_min = -1.0;
  EXPECT_NE(message_of(U, Y, 1.0, o).find("max_delay_min = -1"), std::string::npos);
}

TEST(Identify, DelayBoundIsRespected) {
  // True delay 7.25 min, bound 5 min: the delay ends on its bound and is reported so.
  const std::vector<ElementModel> truth = {{0.8, 7.25, 30.0, 2.0}};
  const Eigen::MatrixXd U = prbs_inputs(1, 6, 8, 0, 1008, 1.0);
  const Eigen::MatrixXd Y = plant_outputs(truth, 1, 1, 1.0, U);
  IdentifyOptions o;
  o.max_delay_min = 5.0;
  const IdentificationResult r = identify(U, Y, 1.0, o);
  const ElementEstimate& e = r.model.element(0, 0);
  EXPECT_LE(e.value.delay_min, 5.0);
  EXPECT_EQ(e.at_bound[kDelay], Bound::upper);
  EXPECT_TRUE(std::isnan(e.std_error.delay_min));
}

}  // namespace
}  // namespace excite::host
