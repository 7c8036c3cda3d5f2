// SPDX-License-Identifier: MIT
// Closed loops in process: a controller of sim/control on a plant of sim/library, sample by
// sample through sim::Plant::step. The plant returns y(k) in the same call that takes u(k),
// so the controller's output at k is applied from k+1: one sample of loop delay, which
// the DMC's model carries (StepModel::delayed(1)). GIVEN a setpoint step, THEN the CVs
// reach it with no offset at steady state, and the MVs never leave their limits (which
// bind on the way).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/control/dmc.hpp"
#include "sim/control/integral_controllability.hpp"
#include "sim/control/pi.hpp"
#include "sim/control/step_model.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::control {
namespace {

struct LoopRecord {
  Eigen::MatrixXd y;  // samples × p
  Eigen::MatrixXd u;  // samples × n, the MVs the plant received
  int clamped = 0;    // MV-samples on a box limit
  int move_limited = 0;
};

LoopRecord run_loop(Plant& plant, Controller& controller, const Eigen::VectorXd& setpoint,
                    int samples) {
  const auto n = static_cast<std::size_t>(plant.inputs());
  const auto p = static_cast<std::size_t>(plant.outputs());
  plant.reset(controller.sample_time_min());
  controller.reset();
  std::vector<double> applied(n, 0.0), y(p), u(n), offsets(n, 0.0);
  LoopRecord r;
  r.y.resize(samples, static_cast<Eigen::Index>(p));
  r.u.resize(samples, static_cast<Eigen::Index>(n));
  for (int k = 0; k < samples; ++k) {
    plant.step(applied, y);  // y(k); the previous output held over [kT, (k+1)T)
    for (std::size_t c = 0; c < p; ++c) r.y(k, static_cast<Eigen::Index>(c)) = y[c];
    for (std::size_t j = 0; j < n; ++j) r.u(k, static_cast<Eigen::Index>(j)) = applied[j];
    const StepReport report =
        controller.step(y, std::span<const double>(setpoint.data(), p), offsets, u);
    EXPECT_EQ(report.status, StepStatus::ok) << "sample " << k;
    for (std::size_t j = 0; j < n; ++j) {
      applied[j] = u[j] + offsets[j];
      const MvStatus s = controller.mv_status()[j];
      r.clamped += s == MvStatus::clamped_low || s == MvStatus::clamped_high ? 1 : 0;
      r.move_limited += s == MvStatus::move_limited ? 1 : 0;
    }
  }
  return r;
}

// The plant's step model with each element's gain off by up to ±8 % (a fixed pattern whose
// principal minors keep the plant's signs): the controller's model is wrong, as in a plant.
StepModel perturbed(const StepModel& exact, const Eigen::MatrixXd& plant_gain) {
  const Eigen::Matrix4d factor = (Eigen::Matrix4d() << 1.08, 0.95, 1.03, 0.92,  //
                                  0.94, 1.06, 0.97, 1.05,                       //
                                  1.02, 0.93, 1.07, 0.96,                       //
                                  0.98, 1.04, 0.95, 1.08)
                                     .finished();
  StepModel out = exact;
  for (Eigen::MatrixXd& s : out.coefficients) s = s.cwiseProduct(factor);
  EXPECT_TRUE(check_integral_controllability(out.gain(), plant_gain, "perturbed").ok());
  return out;
}

TEST(ClosedLoop, Alatiqi4x4UnderDmcTracksASetpointStepWithinItsMvLimits) {
  auto plant = make_plant("alatiqi4x4");
  // GIVEN a DMC on a perturbed model of the plant (P = 150, M = 5), a step of 0.5 in CV 1
  // and 0.3 in CV 3, MV limits 30 % above the steady-state MVs the step needs, moves of at
  // most a tenth of them per minute.
  const Eigen::Vector4d setpoint(0.5, 0.0, 0.3, 0.0);
  const Eigen::VectorXd u_final = plant->static_gain().lu().solve(setpoint);
  const double reach = u_final.cwiseAbs().maxCoeff();
  DmcSettings s;
  s.prediction_horizon = 150;
  s.control_horizon = 5;
  s.mv.assign(4, MvSettings{-1.3 * reach, 1.3 * reach, 0.1 * reach, 0.1});
  s.cv.assign(4, CvSettings{});
  DmcController dmc(perturbed(step_model(*plant, 1.0).delayed(1), plant->static_gain()), s);
  // WHEN the loop runs 1500 min
  const LoopRecord r = run_loop(*plant, dmc, setpoint, 1500);
  // THEN every CV sits on its setpoint over the last 100 min (no offset: the bias of the
  // DMC prediction, since the model's gains are wrong) …
  for (Eigen::Index c = 0; c < 4; ++c) {
    const double worst = (r.y.col(c).tail(100).array() - setpoint(c)).abs().maxCoeff();
    EXPECT_LT(worst, 1e-4) << "CV " << c + 1;
  }
  // … the MVs reach G(0)⁻¹·setpoint, never left their limits, and the limits did bind.
  EXPECT_LT((r.u.bottomRows(1).transpose() - u_final).cwiseAbs().maxCoeff(), 1e-3 * reach);
  EXPECT_LE(r.u.cwiseAbs().maxCoeff(), 1.3 * reach * (1 + 1e-12));
  EXPECT_LE((r.u.bottomRows(r.u.rows() - 1) - r.u.topRows(r.u.rows() - 1)).cwiseAbs().maxCoeff(),
            0.1 * reach * (1 + 1e-12));
  EXPECT_GT(r.move_limited + r.clamped, 0) << "the limits must have been reached to test them";
}

TEST(ClosedLoop, WoodBerryUnderDecentralisedPiTracksASetpointStepWithinItsMvLimits) {
  auto plant = make_plant("woodberry2x2");
  // GIVEN the BLT tuning of Luyben (1986): xD–R: Kc = 0.375, τI = 8.29 min; xB–S:
  // Kc = −0.075, τI = 23.6 min; MVs within ±0.3.
  PiSettings s;
  s.inputs = 2;
  s.outputs = 2;
  s.loops = {PiLoop{0, 0, 0.375, 8.29}, PiLoop{1, 1, -0.075, 23.6}};
  s.mv.assign(2, MvSettings{-0.3, 0.3, kUnlimited, 1.0});
  PiController pi(s);
  const Eigen::Vector2d setpoint(1.0, 0.0);
  // WHEN the loop runs 1000 min
  const LoopRecord r = run_loop(*plant, pi, setpoint, 1000);
  // THEN no offset, the MVs at G(0)⁻¹·setpoint, within ±0.3, which the first move reached.
  for (Eigen::Index c = 0; c < 2; ++c) {
    EXPECT_LT((r.y.col(c).tail(100).array() - setpoint(c)).abs().maxCoeff(), 1e-4) << "CV " << c + 1;
  }
  const Eigen::VectorXd u_final = plant->static_gain().lu().solve(setpoint);
  EXPECT_LT((r.u.bottomRows(1).transpose() - u_final).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LE(r.u.cwiseAbs().maxCoeff(), 0.3);
  EXPECT_GT(r.clamped, 0);
}

}  // namespace
}  // namespace excite::sim::control
