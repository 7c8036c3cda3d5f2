// SPDX-License-Identifier: MIT
// DMC / QDMC (sim/control/dmc.hpp) against moves computed by hand from
// Δu = (SᵀW_yS + W_Δu)⁻¹ SᵀW_y e, with constraints inactive (the QP's move is the
// unconstrained one) and active (a move limit, an MV box limit, a CV zone), and the free
// response of the DMC prediction after a move.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "sim/control/dmc.hpp"

namespace excite::sim::control {
namespace {

// 1×1: S_1 = 1, S_2 = 1.5, S_3 = 1.75, S_4 = 1.875 = S_N (N = 4), T = 1 min.
StepModel siso_model() {
  StepModel m;
  m.inputs = 1;
  m.outputs = 1;
  for (const double s : {0.0, 1.0, 1.5, 1.75, 1.875})
    m.coefficients.push_back(Eigen::MatrixXd::Constant(1, 1, s));
  return m;
}

// P = 3, M = 2, w = 1, λ = 0.5.
DmcSettings siso_settings() {
  DmcSettings s;
  s.prediction_horizon = 3;
  s.control_horizon = 2;
  s.mv = {MvSettings{}};
  s.mv[0].move_suppression = 0.5;
  s.cv = {CvSettings{}};
  return s;
}

double first_move(DmcController& dmc, double y, double sp, double offset = 0.0) {
  double u = 0.0;
  dmc.step(std::span<const double>(&y, 1), std::span<const double>(&sp, 1),
           std::span<const double>(&offset, 1), std::span<double>(&u, 1));
  return u;
}

// S_u = [[1, 0], [1.5, 1], [1.75, 1.5]]; SᵀS + 0.5 I = [[6.8125, 4.125], [4.125, 3.75]]
// (det 8.53125); e = [1, 1, 1], Sᵀe = [4.25, 2.5];
// Δu = [3.75·4.25 − 4.125·2.5, 6.8125·2.5 − 4.125·4.25] / 8.53125 = [5.625, −0.5] / 8.53125.
constexpr double kSisoFirstMove = 5.625 / 8.53125;  // 0.659340…

TEST(Dmc, SisoUnconstrainedMoveIsTheHandComputedOne) {
  DmcController dmc(siso_model(), siso_settings());
  const Eigen::MatrixXd expected_su = (Eigen::MatrixXd(3, 2) << 1, 0, 1.5, 1, 1.75, 1.5).finished();
  EXPECT_EQ(dmc.dynamic_matrix(), expected_su);
  EXPECT_NEAR(first_move(dmc, 0.0, 1.0), kSisoFirstMove, 1e-14);
}

TEST(Dmc, TheFreeResponseCarriesTheLastMoveThroughTheStepModel) {
  DmcController dmc(siso_model(), siso_settings());
  const double du = first_move(dmc, 0.0, 1.0);
  // At k = 1 the plant (here: the model) shows S_1·du; the prediction of k+1…k+3 is
  // S_2·du, S_3·du, S_4·du (bias 0), the last one the truncated model's S_N.
  first_move(dmc, 1.0 * du, 1.0);
  const Eigen::Vector3d expected(1.5 * du, 1.75 * du, 1.875 * du);
  EXPECT_LT((dmc.free_response() - expected).cwiseAbs().maxCoeff(), 1e-14);
  // A measured CV 0.1 above the model's prediction shifts the whole prediction by 0.1.
  DmcController biased(siso_model(), siso_settings());
  first_move(biased, 0.0, 1.0);
  first_move(biased, 1.0 * du + 0.1, 1.0);
  EXPECT_LT(
      (biased.free_response() - expected - Eigen::Vector3d::Constant(0.1)).cwiseAbs().maxCoeff(),
      1e-14);
}

TEST(Dmc, AKnownOffsetIsAKnownMoveInThePrediction) {
  // Offset 0.2 applied at k = 0: f = 0.2·[1, 1.5, 1.75] = [0.2, 0.3, 0.35], e = −f,
  // Sᵀe = −[1.2625, 0.825]; Δu_0 = −(3.75·1.2625 − 4.125·0.825) / 8.53125 = −1.33125 / 8.53125.
  DmcController dmc(siso_model(), siso_settings());
  EXPECT_NEAR(first_move(dmc, 0.0, 0.0, 0.2), -1.33125 / 8.53125, 1e-14);
}

// 2×2, N = 2: S_1 = [[1, 0.5], [0.2, 2]], S_2 = [[1.5, 0.8], [0.4, 3]]; P = 2, M = 1,
// W_y = diag(1, 2), W_Δu = diag(0.1, 0.2), setpoints (1, −1) from rest.
// SᵀW_yS + W_Δu = [[3.75, 4.9], [4.9, 27.09]] (det 77.5775), SᵀW_y e = [1.3, −8.7]:
// Δu = [27.09·1.3 + 4.9·8.7, −3.75·8.7 − 4.9·1.3] / 77.5775 = [2022/2015, −1418/2821].
TEST(Dmc, TwoByTwoUnconstrainedMoveIsTheHandComputedOne) {
  StepModel m;
  m.inputs = 2;
  m.outputs = 2;
  m.coefficients = {Eigen::MatrixXd::Zero(2, 2),
                    (Eigen::MatrixXd(2, 2) << 1, 0.5, 0.2, 2).finished(),
                    (Eigen::MatrixXd(2, 2) << 1.5, 0.8, 0.4, 3).finished()};
  DmcSettings s;
  s.prediction_horizon = 2;
  s.control_horizon = 1;
  s.mv = {MvSettings{}, MvSettings{}};
  s.mv[0].move_suppression = 0.1;
  s.mv[1].move_suppression = 0.2;
  s.cv = {CvSettings{}, CvSettings{}};
  s.cv[1].weight = 2.0;
  DmcController dmc(m, s);
  const double y[2] = {0, 0}, sp[2] = {1, -1}, offset[2] = {0, 0};
  double u[2];
  const StepReport r = dmc.step(y, sp, offset, u);
  EXPECT_EQ(r.status, StepStatus::ok);
  EXPECT_NEAR(u[0], 2022.0 / 2015.0, 1e-13);
  EXPECT_NEAR(u[1], -1418.0 / 2821.0, 1e-13);
}

TEST(Dmc, WithLimitsFarAwayTheQpMoveIsTheUnconstrainedOne) {
  DmcSettings s = siso_settings();
  s.mv[0] = {-10.0, 10.0, 5.0, 0.5};
  s.cv[0].limit_low = -20.0;
  s.cv[0].limit_high = 20.0;
  DmcController dmc(siso_model(), s);
  EXPECT_EQ(dmc.constraint_rows(), 4 + 4 + 6 + 1);  // moves, box, CV rows, slack ≥ 0
  double y = 0.0, sp = 1.0, offset = 0.0, u = 0.0;
  const StepReport r = dmc.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1});
  EXPECT_EQ(r.qp_iterations, 0);
  EXPECT_EQ(r.active_constraints, 0);
  EXPECT_NEAR(u, kSisoFirstMove, 1e-14);
  EXPECT_EQ(dmc.mv_status()[0], MvStatus::ok);
}

TEST(Dmc, AMoveLimitBelowTheUnconstrainedMoveHoldsBothMovesAtTheLimit) {
  // |Δu| ≤ 0.3: Δu_0 = 0.3 (its gradient 6.8125·0.3 + 4.125·0.3 − 4.25 = −0.96875 < 0 still
  // pushes up) and Δu_1 = min(0.3, (2.5 − 4.125·0.3)/3.75 = 0.3367) = 0.3.
  DmcSettings s = siso_settings();
  s.mv[0].max_move = 0.3;
  DmcController dmc(siso_model(), s);
  EXPECT_NEAR(first_move(dmc, 0.0, 1.0), 0.3, 1e-14);
  EXPECT_EQ(dmc.mv_status()[0], MvStatus::move_limited);
}

TEST(Dmc, AnMvBoxLimitHoldsTheMvAtItsLimit) {
  // u ≤ 0.5 at both moves: Δu_0 ≤ 0.5 and Δu_0 + Δu_1 ≤ 0.5. Along Δu_0 + Δu_1 = 0.5 the
  // optimum is Δu_0 = 1.5625/2.3125 > 0.5, so both bind: (0.5, 0), multipliers
  // 0.84375 − 0.4375 and 0.4375, both ≥ 0.
  DmcSettings s = siso_settings();
  s.mv[0].max = 0.5;
  DmcController dmc(siso_model(), s);
  double y = 0.0, sp = 1.0, offset = 0.0, u = 0.0;
  const StepReport r = dmc.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1});
  EXPECT_NEAR(u, 0.5, 1e-14);
  EXPECT_EQ(r.active_constraints, 2);
  EXPECT_EQ(dmc.mv_status()[0], MvStatus::clamped_high);
  // The box applies to the MV the plant receives: with a known offset of 0.2 the
  // controller's own output stops at 0.3.
  DmcController with_offset(siso_model(), s);
  EXPECT_NEAR(first_move(with_offset, 0.0, 1.0, 0.2), 0.3, 1e-14);
}

TEST(Dmc, AnMvPushedOutOfItsBoxWalksBackAtItsLargestMove) {
  // max = 0.5, |Δu| ≤ 0.1; a known offset of 0.8 puts the applied MV at 0.8: the box is out
  // of reach this sample, so it is widened to what the move limit reaches (0.7) and the
  // controller moves −0.1 — no infeasible QP.
  DmcSettings s = siso_settings();
  s.mv[0].max = 0.5;
  s.mv[0].max_move = 0.1;
  DmcController dmc(siso_model(), s);
  double y = 0.0, sp = 0.0, offset = 0.8, u = 0.0;
  const StepReport r = dmc.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1});
  EXPECT_EQ(r.status, StepStatus::ok);
  EXPECT_NEAR(u, -0.1, 1e-14);
}

TEST(Dmc, AtTheQpIterationCapTheMoveIsTheUnconstrainedOneClipped) {
  // The box case above needs two active constraints; a cap of one iteration stops the QP,
  // and the move falls back to the unconstrained 0.6593… clipped to max = 0.5.
  DmcSettings s = siso_settings();
  s.mv[0].max = 0.5;
  s.max_qp_iterations = 1;
  DmcController dmc(siso_model(), s);
  double y = 0.0, sp = 1.0, offset = 0.0, u = 0.0;
  EXPECT_EQ(dmc.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1}).status, StepStatus::qp_fallback);
  EXPECT_EQ(u, 0.5);
}

TEST(Dmc, AZoneCvMovesOnlyWhenItsPredictionLeavesTheZone) {
  // A zone CV: no tracking; zone [−0.2, 0.2] about the setpoint 0, slack weight 1e8.
  DmcSettings s = siso_settings();
  s.cv[0].zone = true;
  s.cv[0].zone_low = -0.2;
  s.cv[0].zone_high = 0.2;
  s.slack_weight = 1e8;
  {
    // Inside the zone (a disturbance of 0.1 seen through the bias): no move.
    DmcController dmc(siso_model(), s);
    EXPECT_EQ(first_move(dmc, 0.1, 0.0), 0.0);
  }
  // A disturbance of 0.5: the prediction 0.5 + [1, 1.5Δu_0 + Δu_1, 1.75Δu_0 + 1.5Δu_1]
  // must come to ≤ 0.2: the cheapest moves are Δu_0 = −0.3 (row 1 binds) and Δu_1 = 0
  // (rows 2, 3 hold with room); the soft bound gives way by about λ·0.3/ρ.
  DmcController dmc(siso_model(), s);
  EXPECT_NEAR(first_move(dmc, 0.5, 0.0), -0.3, 1e-6);
  // The zone moves with the setpoint: at setpoint 0.4 the same CV is inside.
  DmcController moved(siso_model(), s);
  EXPECT_EQ(first_move(moved, 0.5, 0.4), 0.0);
}

TEST(Dmc, ANonFiniteMeasurementHoldsTheOutput) {
  DmcController dmc(siso_model(), siso_settings());
  const double u0 = first_move(dmc, 0.0, 1.0);
  double y = std::numeric_limits<double>::quiet_NaN(), sp = 1.0, offset = 0.0, u = -1.0;
  EXPECT_EQ(dmc.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1}).status, StepStatus::held);
  EXPECT_EQ(u, u0);
  double wrong[2] = {0, 0};
  EXPECT_EQ(dmc.step({wrong, 2}, {&sp, 1}, {&offset, 1}, {&u, 1}).status, StepStatus::held);
}

TEST(Dmc, ResetStartsAgainFromRest) {
  DmcController dmc(siso_model(), siso_settings());
  first_move(dmc, 0.0, 1.0);
  first_move(dmc, 0.3, 1.0);
  dmc.reset();
  EXPECT_NEAR(first_move(dmc, 0.0, 1.0), kSisoFirstMove, 1e-14);
}

TEST(Dmc, RefusesSettingsByName) {
  const auto message = [](DmcSettings s) {
    try {
      DmcController(siso_model(), std::move(s));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  DmcSettings s = siso_settings();
  s.control_horizon = 4;
  EXPECT_EQ(message(s), "dmc.control_horizon = 4, expected an integer 1..prediction_horizon (3)");
  s = siso_settings();
  s.mv[0].move_suppression = 0.0;
  EXPECT_EQ(message(s), "mv[0].move_suppression = 0, expected a finite number > 0");
  s = siso_settings();
  s.cv.clear();
  EXPECT_EQ(message(s), "cv = 0, expected 1 CV entries (the model's outputs)");
}

}  // namespace
}  // namespace excite::sim::control
