// SPDX-License-Identifier: MIT
#include "host/measures/input_measures.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace excite::host {
namespace {

Eigen::VectorXd vec(std::initializer_list<double> values) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (const double x : values) v(i++) = x;
  return v;
}

// x = [1 1 −1 −1 1]: steps [0 −2 0 2], two switches out of four transitions,
// mean 0.2, RMS 1, range 2 — every value below worked by hand.
TEST(MeasureChannel, BinarySequenceMatchesHandComputedValues) {
  const ChannelMeasures m = measure_channel(vec({1, 1, -1, -1, 1}));
  EXPECT_DOUBLE_EQ(m.phi, 50.0);        // (1 − 2/4)·100
  EXPECT_DOUBLE_EQ(m.phi_smooth, 0.5);  // 1 − 8/(4·4)
  EXPECT_DOUBLE_EQ(m.rms, 1.0);
  EXPECT_DOUBLE_EQ(m.crest_factor, 1.0);
  EXPECT_NEAR(m.peak_factor, 1.0 / std::sqrt(2.0), 1e-15);  // 2/(2√2·1)
  EXPECT_NEAR(m.pips, 100.0 * std::sqrt(0.96), 1e-12);      // 200·√(1 − 0.04)/2
  EXPECT_DOUBLE_EQ(m.min, -1.0);
  EXPECT_DOUBLE_EQ(m.max, 1.0);
  EXPECT_DOUBLE_EQ(m.max_step, 2.0);
}

// x = [0 1 2 3]: changes every sample (Φ = 0), all steps equal (Φ_i = 0),
// mean 1.5, RMS √3.5.
TEST(MeasureChannel, RampChangesEverySample) {
  const ChannelMeasures m = measure_channel(vec({0, 1, 2, 3}));
  EXPECT_DOUBLE_EQ(m.phi, 0.0);
  EXPECT_DOUBLE_EQ(m.phi_smooth, 0.0);
  EXPECT_NEAR(m.rms, std::sqrt(3.5), 1e-15);
  EXPECT_NEAR(m.crest_factor, 3.0 / std::sqrt(3.5), 1e-15);
  EXPECT_NEAR(m.pips, 200.0 * std::sqrt(3.5 - 2.25) / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(m.max_step, 1.0);
}

TEST(MeasureChannel, ConstantIsFullyPlantFriendlyAndHasNoPips) {
  const ChannelMeasures m = measure_channel(vec({2, 2, 2}));
  EXPECT_DOUBLE_EQ(m.phi, 100.0);
  EXPECT_DOUBLE_EQ(m.phi_smooth, 1.0);
  EXPECT_DOUBLE_EQ(m.crest_factor, 1.0);
  EXPECT_TRUE(std::isnan(m.pips));
}

TEST(MeasureChannel, RejectsASingleSample) {
  EXPECT_THROW(measure_channel(vec({1})), std::invalid_argument);
}

TEST(MeasureInputs, AveragesEveryFieldOverChannels) {
  Eigen::MatrixXd table(5, 2);
  table.col(0) = vec({1, 1, -1, -1, 1});
  table.col(1) = vec({0, 1, 2, 3, 4});
  const InputMeasures m = measure_inputs(table);
  ASSERT_EQ(m.channels.size(), 2U);
  EXPECT_DOUBLE_EQ(m.average.phi, (50.0 + 0.0) / 2.0);
  EXPECT_DOUBLE_EQ(m.average.crest_factor,
                   (m.channels[0].crest_factor + m.channels[1].crest_factor) / 2.0);
  EXPECT_DOUBLE_EQ(m.average.max, (1.0 + 4.0) / 2.0);
}

// A channel that moves in 10 of 40 samples: CF 1 over its active span, √(40/10) = 2 over
// the table (the relation of sequential and simultaneous multisines); a still channel is
// left out of the average.
TEST(ActiveCrestFactor, IsTakenOverTheSpanWhereTheChannelMoves) {
  Eigen::MatrixXd table = Eigen::MatrixXd::Zero(40, 2);
  for (Eigen::Index k = 10; k < 20; ++k) table(k, 0) = (k % 2 == 0) ? 1.0 : -1.0;
  EXPECT_DOUBLE_EQ(active_crest_factor_avg(table), 1.0);
  EXPECT_DOUBLE_EQ(measure_inputs(table).channels[0].crest_factor, 2.0);
  EXPECT_TRUE(std::isnan(active_crest_factor_avg(Eigen::MatrixXd::Zero(5, 1))));
}

}  // namespace
}  // namespace excite::host
