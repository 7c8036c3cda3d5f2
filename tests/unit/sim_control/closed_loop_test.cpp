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
#include <functional>
#include <vector>

#include "sim/control/dmc.hpp"
#include "sim/control/integral_controllability.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/control/pi.hpp"
#include "sim/control/step_model.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::control {
namespace {

struct LoopRecord {
  Eigen::MatrixXd y;       // samples × p
  Eigen::MatrixXd u;       // samples × n, the MVs the plant received
  Eigen::MatrixXd u_ctrl;  // samples × n, the controller's outputs
  int clamped = 0;         // MV-samples on a box limit
  int move_limited = 0;
};

// The known MV offsets of sample k (a test signal the plant receives on top of u_ctrl).
using Offsets = std::function<void(int k, std::vector<double>& offsets)>;

LoopRecord run_loop(Plant& plant, Controller& controller, const Eigen::VectorXd& setpoint,
                    int samples, const Offsets& offsets_of = {}) {
  const auto n = static_cast<std::size_t>(plant.inputs());
  const auto p = static_cast<std::size_t>(plant.outputs());
  plant.reset(controller.sample_time_min());
  controller.reset();
  std::vector<double> applied(n, 0.0), y(p), u(n), offsets(n, 0.0);
  LoopRecord r;
  r.y.resize(samples, static_cast<Eigen::Index>(p));
  r.u.resize(samples, static_cast<Eigen::Index>(n));
  r.u_ctrl.resize(samples, static_cast<Eigen::Index>(n));
  for (int k = 0; k < samples; ++k) {
    if (offsets_of) offsets_of(k, offsets);
    plant.step(applied, y);  // y(k); the previous output held over [kT, (k+1)T)
    for (std::size_t c = 0; c < p; ++c) r.y(k, static_cast<Eigen::Index>(c)) = y[c];
    for (std::size_t j = 0; j < n; ++j) r.u(k, static_cast<Eigen::Index>(j)) = applied[j];
    const StepReport report =
        controller.step(y, std::span<const double>(setpoint.data(), p), offsets, u);
    EXPECT_EQ(report.status, StepStatus::ok) << "sample " << k;
    for (std::size_t j = 0; j < n; ++j) {
      r.u_ctrl(k, static_cast<Eigen::Index>(j)) = u[j];
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

TEST(ClosedLoop, QdmcKeepsAnotherCvInsideItsSoftLimitsWhileTrackingASetpointStep) {
  auto plant = make_plant("alatiqi4x4");
  // GIVEN a DMC on the plant's model, a setpoint step of 0.5 in CV 1, the other CVs at 0.
  DmcSettings s;
  s.prediction_horizon = 150;
  s.control_horizon = 5;
  s.mv.assign(4, MvSettings{-kUnlimited, kUnlimited, kUnlimited, 0.1});
  s.cv.assign(4, CvSettings{});
  s.slack_weight = 1e6;
  const StepModel model = step_model(*plant, 1.0).delayed(1);
  const Eigen::Vector4d setpoint(0.5, 0.0, 0.0, 0.0);
  DmcController free_cvs(model, s);
  const LoopRecord unlimited = run_loop(*plant, free_cvs, setpoint, 600);
  const double swing = unlimited.y.col(3).cwiseAbs().maxCoeff();
  // WHEN CV 4 gets soft limits at a third of the swing it had without them
  const double limit = swing / 3.0;
  s.cv[3].limit_low = -limit;
  s.cv[3].limit_high = limit;
  DmcController limited_cv(model, s);
  const LoopRecord limited = run_loop(*plant, limited_cv, setpoint, 600);
  // THEN CV 4 stays inside them (to 1 % of the limit: the slack's give), CV 1 still
  // reaches its setpoint.
  EXPECT_GT(swing, 0.01) << "the step must move CV 4 for the limit to mean something";
  EXPECT_LE(limited.y.col(3).cwiseAbs().maxCoeff(), 1.01 * limit);
  EXPECT_LT(std::abs(limited.y(599, 0) - 0.5), 1e-4);
}

TEST(ClosedLoop, ZoneCvsLetAKnownMvDitherThroughThatTrackingCvsCancel) {
  auto plant = make_plant("alatiqi4x4");
  // GIVEN a ±0.05 dither on MV 1 (switching every 20 min), known to the controller.
  const Offsets dither = [](int k, std::vector<double>& offsets) {
    offsets[0] = (k / 20) % 2 ? 0.05 : -0.05;
  };
  DmcSettings s;
  s.prediction_horizon = 150;
  s.control_horizon = 5;
  s.mv.assign(4, MvSettings{-kUnlimited, kUnlimited, kUnlimited, 0.1});
  s.cv.assign(4, CvSettings{});
  const StepModel model = step_model(*plant, 1.0).delayed(1);
  const Eigen::Vector4d setpoint = Eigen::Vector4d::Zero();
  // WHEN every CV tracks its setpoint, the controller works against the dither …
  DmcController tracking(model, s);
  const LoopRecord tracked = run_loop(*plant, tracking, setpoint, 400, dither);
  EXPECT_GT(tracked.u_ctrl.cwiseAbs().maxCoeff(), 0.01);
  // … and when every CV is a zone wide enough for the dither's effect, it never moves.
  const double effect = 0.05 * plant->static_gain().col(0).cwiseAbs().maxCoeff();
  for (CvSettings& c : s.cv) {
    c.zone = true;
    c.zone_low = -2.0 * effect;
    c.zone_high = 2.0 * effect;
  }
  DmcController zones(model, s);
  const LoopRecord zoned = run_loop(*plant, zones, setpoint, 400, dither);
  EXPECT_EQ(zoned.u_ctrl.cwiseAbs().maxCoeff(), 0.0);
  // The CVs are then the open-loop response to the dither (applied one sample late).
  Eigen::MatrixXd du = Eigen::MatrixXd::Zero(400, 4);
  std::vector<double> offsets(4, 0.0);
  for (int k = 0; k + 1 < 400; ++k) {
    dither(k, offsets);
    du(k + 1, 0) = offsets[0];
  }
  const Eigen::MatrixXd open_loop = plant->simulate(du, 1.0);
  EXPECT_LT((zoned.y - open_loop).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_GT(zoned.y.cwiseAbs().maxCoeff(), 0.1 * effect) << "the dither must reach the CVs";
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
    EXPECT_LT((r.y.col(c).tail(100).array() - setpoint(c)).abs().maxCoeff(), 1e-4)
        << "CV " << c + 1;
  }
  const Eigen::VectorXd u_final = plant->static_gain().lu().solve(setpoint);
  EXPECT_LT((r.u.bottomRows(1).transpose() - u_final).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LE(r.u.cwiseAbs().maxCoeff(), 0.3);
  EXPECT_GT(r.clamped, 0);
}

// The example controller files (sim/control/examples) run as written: read, built on their
// model for their plant, and closing the loop on a setpoint step.
class ExampleFile : public ::testing::TestWithParam<const char*> {};

TEST_P(ExampleFile, RunsItsPlantToASetpointStep) {
  const ControllerFile file =
      load_controller_file(std::string(EXCITE_CONTROL_EXAMPLES) + "/" + GetParam());
  auto model = load_model(file);
  auto plant = make_plant(file.model.plant);
  const Eigen::MatrixXd g0 = plant->static_gain();
  auto controller = make_controller(file, *model, &g0);
  Eigen::VectorXd setpoint = Eigen::VectorXd::Zero(plant->outputs());
  setpoint(0) = 0.5;
  const LoopRecord r = run_loop(*plant, *controller, setpoint, 1000);
  EXPECT_LT((r.y.bottomRows(1).transpose() - setpoint).cwiseAbs().maxCoeff(), 1e-3);
}

// colaA.dmc.toml: a DMC on the textbook LV model (linear, one lag) running the nonlinear
// tray-by-tray column, as an MPC's model and its plant differ; integrally controllable for
// colaA's G(0), and bringing both CVs to a step of half their test limits (the strong
// direction: a step of yD alone needs about 0.04 kmol/min, beyond the MVs' ±0.02) with both
// MVs in their box.
TEST(ExampleFile, ColaAsDmcOnTheTextbookLvModelRunsTheNonlinearColumn) {
  const ControllerFile file =
      load_controller_file(std::string(EXCITE_CONTROL_EXAMPLES) + "/colaA.dmc.toml");
  auto model = load_model(file);
  auto plant = make_plant("colaA");
  const Eigen::MatrixXd g0 = plant->static_gain();
  auto controller = make_controller(file, *model, &g0);
  const Eigen::VectorXd setpoint = Eigen::VectorXd::Constant(2, 0.001);
  const LoopRecord r = run_loop(*plant, *controller, setpoint, 1500);
  EXPECT_LT((r.y.bottomRows(1).transpose() - setpoint).cwiseAbs().maxCoeff(), 2e-5)
      << r.y.bottomRows(1);
  EXPECT_LE(r.u.cwiseAbs().maxCoeff(), 0.02 + 1e-12);
}

INSTANTIATE_TEST_SUITE_P(
    SimControlExamples, ExampleFile,
    ::testing::Values("alatiqi4x4.dmc.toml", "woodberry2x2.pi.toml"), [](const auto& param_info) {
      return std::string(param_info.param).substr(0, std::string(param_info.param).find('.'));
    });

}  // namespace
}  // namespace excite::sim::control
