// SPDX-License-Identifier: MIT
// Predictive amplitude control (issue 26 §2): the scale keeps the model's prediction ± 2σ
// inside the CV limits, and the plants the uncertainty allows stay inside them too.
#include "host/adaptive/amplitude_control.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace excite::host {
namespace {

constexpr double kT = 1.0;  // min

// Wood and Berry's column with a small second lag on every element (two poles + delay).
IdentifiedModel column_model() {
  IdentifiedModel m;
  m.inputs = m.outputs = 2;
  m.sample_time_min = kT;
  const double K[2][2] = {{12.8, -18.9}, {6.6, -19.4}};
  const double Td[2][2] = {{1.0, 3.0}, {7.0, 3.0}};
  const double Tp[2][2] = {{16.7, 21.0}, {10.9, 14.4}};
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      ElementEstimate e;
      e.value.gain = K[j][i];
      e.value.delay_min = Td[j][i];
      e.value.tau1_min = Tp[j][i];
      e.value.tau2_min = 2.0;
      m.elements.push_back(e);  // covariance NaN: every parameter known
    }
  }
  return m;
}

// A deterministic ±1 binary sequence per input (a 7-bit LFSR, the two inputs shifted).
Eigen::MatrixXd binary_segment(Eigen::Index rows) {
  Eigen::MatrixXd u(rows, 2);
  unsigned state = 0x5Bu;
  std::vector<double> bits;
  for (Eigen::Index k = 0; k < rows + 40; ++k) {
    const unsigned bit = ((state >> 6) ^ (state >> 5)) & 1u;
    state = ((state << 1) | bit) & 0x7Fu;
    bits.push_back(bit ? 1.0 : -1.0);
  }
  for (Eigen::Index k = 0; k < rows; ++k) {
    // Each level held 8 samples (T_sw = 8 T), u2 a quarter period behind.
    u(k, 0) = bits[static_cast<std::size_t>(k / 8)];
    u(k, 1) = bits[static_cast<std::size_t>(k / 8 + 5)];
  }
  return u;
}

CvLimits symmetric(double a, double b) {
  CvLimits l;
  l.low = Eigen::Vector2d(-a, -b);
  l.high = Eigen::Vector2d(a, b);
  return l;
}

// The model's response to the segment followed by `tail` rows of baseline.
Eigen::MatrixXd response(const IdentifiedModel& m, const Eigen::MatrixXd& u, Eigen::Index tail) {
  Eigen::MatrixXd U = Eigen::MatrixXd::Zero(u.rows() + tail, u.cols());
  U.topRows(u.rows()) = u;
  return simulate(m, U);
}

bool inside(const Eigen::MatrixXd& y, const CvLimits& l) {
  for (Eigen::Index j = 0; j < y.cols(); ++j) {
    if (y.col(j).maxCoeff() > l.high(j) || y.col(j).minCoeff() < l.low(j)) return false;
  }
  return true;
}

TEST(ScaleSegment, AnExactModelIsScaledOntoItsBindingLimit) {
  const IdentifiedModel m = column_model();
  const Eigen::MatrixXd u = binary_segment(400);
  const CvLimits limits = symmetric(5.0, 4.0);
  ASSERT_FALSE(inside(response(m, u, 200), limits));  // the unscaled segment leaves them

  const SegmentScale s = scale_segment(m, Eigen::MatrixXd(0, 2), u, limits);
  ASSERT_GT(s.scale, 0.0);
  ASSERT_LT(s.scale, 1.0);
  ASSERT_GE(s.binding_output, 0);
  EXPECT_NE(s.reason.find("limit"), std::string::npos) << s.reason;
  const Eigen::MatrixXd y = response(m, s.scale * u, 200);
  EXPECT_TRUE(inside(y, limits));
  // It binds: the peak of the binding output is at its limit (nothing is wasted) …
  const auto j = static_cast<Eigen::Index>(s.binding_output);
  EXPECT_NEAR(y.col(j).cwiseAbs().maxCoeff(), limits.high(j), 1e-9 * limits.high(j));
  // … and a little more leaves it.
  EXPECT_FALSE(inside(response(m, 1.001 * s.scale * u, 200), limits));
}

TEST(ScaleSegment, ASegmentWithRoomIsNotScaledUp) {
  const IdentifiedModel m = column_model();
  const SegmentScale s =
      scale_segment(m, Eigen::MatrixXd(0, 2), 0.01 * binary_segment(200), symmetric(50, 50));
  EXPECT_EQ(s.scale, 1.0);
  EXPECT_EQ(s.binding_output, -1);
  EXPECT_EQ(s.reason, "");
}

// The band is what the uncertainty allows: plants drawn from the stated covariance leave the
// limits rarely at the uncertain scale, and often at the scale an exact model would take.
TEST(ScaleSegment, PlantsDrawnFromTheCovarianceStayInsideAtTheUncertainScale) {
  IdentifiedModel m = column_model();
  for (ElementEstimate& e : m.elements) {
    e.covariance(kGain, kGain) = std::pow(0.05 * e.value.gain, 2);   // 5 % on every gain
    e.covariance(kTp1, kTp1) = std::pow(0.1 * e.value.tau1_min, 2);  // 10 % on T_p1
    e.covariance(kGain, kTp1) = e.covariance(kTp1, kGain) = 0.0;
  }
  const Eigen::MatrixXd u = binary_segment(400);
  const CvLimits limits = symmetric(5.0, 4.0);
  const double exact = scale_segment(column_model(), Eigen::MatrixXd(0, 2), u, limits).scale;
  const double uncertain = scale_segment(m, Eigen::MatrixXd(0, 2), u, limits).scale;
  EXPECT_LT(uncertain, 0.97 * exact);

  std::mt19937 rng(7);
  std::normal_distribution<double> z;
  int leave_uncertain = 0, leave_exact = 0;
  const int draws = 300;
  for (int d = 0; d < draws; ++d) {
    IdentifiedModel drawn = m;
    for (ElementEstimate& e : drawn.elements) {
      e.value.gain += std::sqrt(e.covariance(kGain, kGain)) * z(rng);
      e.value.tau1_min += std::sqrt(e.covariance(kTp1, kTp1)) * z(rng);
    }
    leave_uncertain += inside(response(drawn, uncertain * u, 200), limits) ? 0 : 1;
    leave_exact += inside(response(drawn, exact * u, 200), limits) ? 0 : 1;
  }
  std::printf(
      "plants leaving the limits: %d of %d at the uncertain scale %.4f, %d at the exact "
      "model's %.4f\n",
      leave_uncertain, draws, uncertain, leave_exact, exact);
  EXPECT_LE(leave_uncertain, draws / 10);
  EXPECT_GE(leave_exact, draws / 3);
}

TEST(ScaleSegment, TheHistoryStillComingTakesRoom) {
  const IdentifiedModel m = column_model();
  const Eigen::MatrixXd u = binary_segment(400);
  const CvLimits limits = symmetric(5.0, 4.0);
  Eigen::MatrixXd history = Eigen::MatrixXd::Zero(20, 2);
  history.col(0).setConstant(0.2);  // y1 still rising by about 2 when the segment starts
  const double fresh = scale_segment(m, Eigen::MatrixXd(0, 2), u, limits).scale;
  const double after = scale_segment(m, history, u, limits).scale;
  EXPECT_LT(after, fresh);
  EXPECT_GT(after, 0.0);

  history.col(0).setConstant(1.0);  // y1 near 12 by the end of the history: beyond 5 alone
  const SegmentScale none = scale_segment(m, history, u, limits);
  EXPECT_EQ(none.scale, 0.0);
  EXPECT_EQ(none.binding_output, 0);
  EXPECT_NE(none.reason.find("history alone"), std::string::npos) << none.reason;
}

TEST(ScaleSegment, AnElementNotEstimatedWhoseInputMovesGivesNoScale) {
  IdentifiedModel m = column_model();
  m.element(1, 1).status = ElementStatus::weak_gain;  // still estimated: simulated
  EXPECT_GT(scale_segment(m, Eigen::MatrixXd(0, 2), binary_segment(100), symmetric(5, 4)).scale,
            0.0);
  m.element(1, 1).status = ElementStatus::input_not_moved;
  const SegmentScale s =
      scale_segment(m, Eigen::MatrixXd(0, 2), binary_segment(100), symmetric(5, 4));
  EXPECT_EQ(s.scale, 0.0);
  EXPECT_NE(s.reason.find("output 2, input 2"), std::string::npos) << s.reason;
  // Its input still: no need to know it.
  Eigen::MatrixXd u = binary_segment(100);
  u.col(1).setZero();
  EXPECT_GT(scale_segment(m, Eigen::MatrixXd(0, 2), u, symmetric(5, 4)).scale, 0.0);
}

TEST(ScaleSegment, BadArgumentsNameTheFieldTheValueAndWhatWasExpected) {
  const IdentifiedModel m = column_model();
  const auto message = [&](const Eigen::MatrixXd& h, const Eigen::MatrixXd& u, const CvLimits& l,
                           ScaleOptions o = {}) {
    try {
      scale_segment(m, h, u, l, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const Eigen::MatrixXd none(0, 2);
  EXPECT_EQ(message(none, Eigen::MatrixXd::Zero(10, 3), symmetric(1, 1)),
            "segment = 10 × 3, expected at least 1 row × 2 (the model's inputs)");
  EXPECT_EQ(message(Eigen::MatrixXd::Zero(4, 1), Eigen::MatrixXd::Zero(10, 2), symmetric(1, 1)),
            "history columns = 1, expected 2 (the model's inputs)");
  CvLimits shifted = symmetric(1, 1);
  shifted.low(0) = 0.5;
  EXPECT_EQ(message(none, Eigen::MatrixXd::Zero(10, 2), shifted),
            "output 1 limits = [0.5, 1] (deviation from the baseline), expected low < 0 < high");
  CvLimits short_limits;
  short_limits.low = Eigen::VectorXd::Constant(1, -1);
  short_limits.high = Eigen::VectorXd::Constant(1, 1);
  EXPECT_EQ(message(none, Eigen::MatrixXd::Zero(10, 2), short_limits),
            "CV limits = 1 low and 1 high, expected 2 each (the model's outputs)");
  Eigen::MatrixXd nan = Eigen::MatrixXd::Zero(10, 2);
  nan(3, 1) = std::nan("");
  EXPECT_NE(message(none, nan, symmetric(1, 1)).find("not finite"), std::string::npos);
  EXPECT_EQ(message(none, Eigen::MatrixXd::Zero(10, 2), symmetric(1, 1), {-1.0, 1.0}),
            "k_sigma = -1, max_scale = 1, expected k_sigma ≥ 0 and max_scale > 0, both finite");
}

}  // namespace
}  // namespace excite::host
