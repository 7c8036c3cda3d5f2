// SPDX-License-Identifier: MIT
// Designs for a test with the controller on (host/design/closed_loop_design.hpp): setpoint
// excitation in CV units sized by the CV test limits, along the output directions or not;
// MV dither; plan version 4 carrying the excitation, open-loop plans unchanged.
#include "host/design/closed_loop_design.hpp"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/plan/codec.hpp"
#include "firmware/signal/mseq.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/table.hpp"

namespace excite::host {
namespace {

std::vector<std::uint8_t> bytes_of(const plan::Plan& p) {
  std::vector<std::uint8_t> out(plan::encoded_size(p));
  const plan::EncodeResult r = plan::encode(p, out);
  EXPECT_TRUE(r.status) << r.status.message();
  return out;
}

SetpointDesignRequest four_cvs(bool directions) {
  SetpointDesignRequest r;
  r.cv_names = {"y1", "y2", "y3", "y4"};
  r.cv_low = Eigen::Vector4d(-1.0, -0.5, -2.0, -1.0);
  r.cv_high = Eigen::Vector4d(1.0, 0.8, 2.0, 0.4);
  r.along_output_directions = directions;
  return r;
}

TEST(SetpointDesign, ChannelsAreTheCvsEachAtItsShareOfItsTestLimit) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const Design d = design_setpoint_excitation(prior, find_preset("prbsUnc"), four_cvs(false), 7);
  EXPECT_EQ(d.plan->meta.excitation, plan::Excitation::setpoint);
  ASSERT_EQ(d.table.cols(), 4);
  // amplitude = 0.5 · min(|low|, high): 0.5, 0.25, 1.0, 0.2
  const Eigen::Vector4d expected(0.5, 0.25, 1.0, 0.2);
  for (Eigen::Index c = 0; c < 4; ++c) {
    EXPECT_NEAR(d.table.col(c).cwiseAbs().maxCoeff(), expected(c), 1e-12) << c;
    EXPECT_EQ(plan::text_of(d.plan->meta.channels[static_cast<std::size_t>(c)].name),
              "y" + std::to_string(c + 1));
  }
  // Uncorrelated across CVs: the normalised cross-correlation of the channels is small.
  const Eigen::MatrixXd t = d.table;
  const Eigen::MatrixXd c = t.transpose() * t;
  for (Eigen::Index i = 0; i < 4; ++i)
    for (Eigen::Index j = i + 1; j < 4; ++j)
      EXPECT_LT(std::abs(c(i, j)) / std::sqrt(c(i, i) * c(j, j)), 0.1) << i << "," << j;
}

// The power of each output direction w_i in r, and the largest normalised correlation
// between two directions: from Wᵀ r(k).
struct DirectionPower {
  double spread = 0.0;       // largest / smallest power
  double correlation = 0.0;  // largest |normalised cross-correlation|
};
DirectionPower in_w_coordinates(const Table& table, const Eigen::MatrixXd& gain) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(gain, Eigen::ComputeFullU);
  const Eigen::MatrixXd s = Eigen::MatrixXd(table) * svd.matrixU();
  const Eigen::MatrixXd c = s.transpose() * s;
  DirectionPower out;
  out.spread = c.diagonal().maxCoeff() / c.diagonal().minCoeff();
  for (Eigen::Index i = 0; i < c.rows(); ++i)
    for (Eigen::Index j = i + 1; j < c.rows(); ++j)
      out.correlation = std::max(out.correlation, std::abs(c(i, j)) / std::sqrt(c(i, i) * c(j, j)));
  return out;
}

TEST(SetpointDesign, AlongTheOutputDirectionsEveryDirectionGetsTheSamePowerUncorrelated) {
  // With equal CV limits an uncorrelated r already has equal power in every direction (its
  // covariance is a multiple of I, which no rotation changes); with the unequal limits here
  // it does not, and the design along W restores it.
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const Design along = design_setpoint_excitation(prior, find_preset("prbsUnc"), four_cvs(true), 7);
  const Design plain =
      design_setpoint_excitation(prior, find_preset("prbsUnc"), four_cvs(false), 7);
  const DirectionPower a = in_w_coordinates(along.table, prior.gain);
  const DirectionPower p = in_w_coordinates(plain.table, prior.gain);
  EXPECT_LT(a.correlation, 0.1);
  EXPECT_LT(a.spread, 1.1);
  EXPECT_GT(p.spread, 2.0);
  const SetpointDesignRequest req = four_cvs(true);
  for (Eigen::Index c = 0; c < 4; ++c) {  // every CV inside its amplitude
    EXPECT_LE(along.table.col(c).cwiseAbs().maxCoeff(),
              0.5 * std::min(-req.cv_low(c), req.cv_high(c)) * (1 + 1e-12));
  }
}

TEST(ClosedLoopPlan, CarriesItsExcitationWhileTheOpenLoopPlanStaysByteIdentical) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const Design open = design_preset(prior, find_preset("prbsUnc"), 7);
  const Design dither = design_mv_dither(prior, find_preset("prbsUnc"), 7);
  EXPECT_EQ(dither.plan->meta.excitation, plan::Excitation::mv);
  EXPECT_EQ(Eigen::MatrixXd(dither.table), Eigen::MatrixXd(open.table));
  const std::vector<std::uint8_t> open_bytes = bytes_of(*open.plan);
  EXPECT_EQ(open_bytes[8], 3);  // version 3: nothing of the closed loop
  EXPECT_EQ(open_bytes, bytes_of(*design_preset(prior, find_preset("prbsUnc"), 7).plan));
  const std::vector<std::uint8_t> dither_bytes = bytes_of(*dither.plan);
  EXPECT_EQ(dither_bytes[8], 4);
  auto back = std::make_unique<plan::Plan>();
  ASSERT_TRUE(plan::decode(dither_bytes, *back, true));
  EXPECT_EQ(back->meta.excitation, plan::Excitation::mv);
}

TEST(SetpointDesign, RefusesADirectionalPresetAndMissingLimitsByName) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  try {
    design_setpoint_excitation(prior, find_preset("prbsSimDir"), four_cvs(false), 7);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("preset = prbsSimDir, expected a plain preset"),
              std::string::npos);
  }
  SetpointDesignRequest open_ended = four_cvs(false);
  open_ended.cv_high(1) = std::numeric_limits<double>::infinity();
  try {
    design_setpoint_excitation(prior, find_preset("prbsUnc"), open_ended, 7);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--limit y2 = -0.5:inf, expected finite test limits"),
              std::string::npos);
  }
}

// The MVs' room (issue 41 §2): under integral action u ≈ G(0)⁻¹ r, and alatiqi4x4's weak
// direction asks for MV moves 1/σ₄ ≈ 6 times r. With the DMC's ±0.6 MV limits, r is scaled
// down until the steady-state moves of the whole table peak at mv_fraction of the room on the
// MV that limits it, the others below; generous limits leave r as the CV limits sized it.
TEST(SetpointDesign, RIsScaledDownUntilItsSteadyStateMvMovesFitTheMvRoom) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const Design by_cvs =
      design_setpoint_excitation(prior, find_preset("prbsUnc"), four_cvs(false), 7);
  SetpointDesignRequest request = four_cvs(false);
  request.mv_low = Eigen::Vector4d::Constant(-0.6);
  request.mv_high = Eigen::Vector4d::Constant(0.6);
  request.mv_fraction = 0.5;
  const Design d = design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7);
  const Eigen::MatrixXd inverse = prior.gain.inverse();
  const Eigen::MatrixXd unsized = Eigen::MatrixXd(by_cvs.table) * inverse.transpose();
  const Eigen::MatrixXd moves = Eigen::MatrixXd(d.table) * inverse.transpose();
  ASSERT_GT(unsized.cwiseAbs().maxCoeff(), 0.3) << "the CV limits alone ask for more than the room";
  EXPECT_NEAR(moves.cwiseAbs().maxCoeff(), 0.3, 1e-9);
  // The same signals, scaled: every channel by one factor, the CVs' ratios kept.
  const double scale = d.table.cwiseAbs().maxCoeff() / by_cvs.table.cwiseAbs().maxCoeff();
  EXPECT_LT(scale, 1.0);
  EXPECT_NEAR(
      (Eigen::MatrixXd(d.table) - scale * Eigen::MatrixXd(by_cvs.table)).cwiseAbs().maxCoeff(), 0.0,
      1e-12);
  EXPECT_NE(
      std::find_if(d.notes.begin(), d.notes.end(),
                   [](const std::string& n) { return n.starts_with("MV room: r scaled by"); }),
      d.notes.end());

  request.mv_low = Eigen::Vector4d::Constant(-1e6);
  request.mv_high = Eigen::Vector4d::Constant(1e6);
  const Design roomy = design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7);
  EXPECT_EQ(Eigen::MatrixXd(roomy.table), Eigen::MatrixXd(by_cvs.table));
}

TEST(SetpointDesign, APrbsPhaseIsTheSameRStartedLaterAndAMultisineRefusesIt) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  SetpointDesignRequest request = four_cvs(false);
  const Design first = design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7);
  request.prbs_phase = 5;
  const Design later = design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7);
  const signal::PrbsSource& prbs = first.plan->recipe.sources[0].prbs;
  const Eigen::Index hold = prbs.hold_samples, rows = first.table.rows();
  ASSERT_EQ(later.table.rows(), rows);
  // A whole period of the m-sequence (4 080 rows, 255 bits of 16): the same rows, 5 bits on.
  ASSERT_EQ(rows, static_cast<Eigen::Index>(signal::mseq_period(prbs.register_length)) * hold);
  for (Eigen::Index k = 0; k < rows; ++k) {
    ASSERT_EQ(Eigen::VectorXd(later.table.row(k)),
              Eigen::VectorXd(first.table.row((k + 5 * hold) % rows)))
        << "row " << k;
  }
  EXPECT_NE(Eigen::MatrixXd(later.table), Eigen::MatrixXd(first.table));
  EXPECT_NE(std::find(later.notes.begin(), later.notes.end(),
                      "the PRBS started 5 switching intervals into its sequence"),
            later.notes.end());
  // A whole period on is the first realisation again.
  request.prbs_phase = signal::mseq_period(prbs.register_length);
  EXPECT_EQ(
      Eigen::MatrixXd(design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7).table),
      Eigen::MatrixXd(first.table));
  request.prbs_phase = 3;
  try {
    (void)design_setpoint_excitation(prior, find_preset("msGlmSim"), request, 7);
    ADD_FAILURE() << "a multisine took a PRBS phase";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "PRBS phase = 3 with preset msGlmSim, expected 0 (it has no PRBS to start later)");
  }
}

TEST(SetpointDesign, RefusesMvLimitsThatDoNotFitThePriorOrAreNotAboutZero) {
  const PriorKnowledge prior = case_study("alatiqi4x4");
  const auto says = [&prior](SetpointDesignRequest request, const std::string& what) {
    try {
      (void)design_setpoint_excitation(prior, find_preset("prbsUnc"), request, 7);
      ADD_FAILURE() << "accepted; expected: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  SetpointDesignRequest three = four_cvs(false);
  three.mv_low = Eigen::Vector3d::Constant(-0.6);
  three.mv_high = Eigen::Vector3d::Constant(0.6);
  says(three,
       "MV limits = 3 low, 3 high, expected one pair per MV of a prior G(0) with one row "
       "per CV (4 x 4)");
  SetpointDesignRequest above = four_cvs(false);
  above.mv_low = Eigen::Vector4d(-0.6, 0.1, -0.6, -0.6);
  above.mv_high = Eigen::Vector4d::Constant(0.6);
  says(above, "MV 2 limits = 0.1:0.6, expected low < 0 < high");
  SetpointDesignRequest share = four_cvs(false);
  share.mv_low = Eigen::Vector4d::Constant(-0.6);
  share.mv_high = Eigen::Vector4d::Constant(0.6);
  share.mv_fraction = 1.5;
  says(share, "MV room fraction = 1.5, expected 0 < f <= 1");
}

}  // namespace
}  // namespace excite::host
