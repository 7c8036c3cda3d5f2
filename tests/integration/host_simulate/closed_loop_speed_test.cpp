// SPDX-License-Identifier: MIT
// How fast a closed loop follows a switch of its setpoints (host/simulate/closed_loop_speed.hpp):
// a hand-computed loop, the weak and strong directions of colaA's textbook model under its
// DMC, and refusals.
#include "host/simulate/closed_loop_speed.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <stdexcept>
#include <string>

#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"
#include "sim/lti/plant_toml.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

// K/(τs + 1) with K = 2, τ = 20 min, under a PI with Kc = 0.5 and τI = τ, by hand in discrete
// time (T = 1 min; the move computed from y(k) acts from k + 1, closed_loop.hpp's timing). The
// PI's zero 1/(1 + T/τI) = 0.9524 cancels the plant's pole e^(−T/τ) = 0.9512, so r → y has
// the poles of z(z − 1) + g = 0, g = Kc·(1 + T/τI)·K·(1 − e^(−T/τ)) = 0.0512: a dominant root
// of 0.9459, a time constant of 18.0 min (the continuous τ/(K·Kc) = 20 min, less the
// velocity form's T/τI).
TEST(ClosedLoopSpeed, APiLoopWhoseZeroCancelsThePlantsPoleFollowsInItsHandComputedTime) {
  auto plant =
      sim::make_linear_plant("siso", sim::plant_from_toml("inputs = [\"u\"]\noutputs = [\"y\"]\n"
                                                          "G = [[\"2 / (20s+1)\"]]\n")
                                         .g);
  const sim::control::ControllerFile file = sim::control::controller_from_toml(
      "kind = \"pi\"\nsample_time_min = 1.0\n[model]\nplant = \"siso.toml\"\n"
      "[[pairing]]\ncv = 1\nmv = 1\nkc = 0.5\nti_min = 20.0\n",
      "siso.pi.toml");
  auto controller = sim::control::make_controller(file, *plant);
  const ClosedLoopSpeed s =
      closed_loop_speed(Eigen::VectorXd::Constant(1, 0.1), 200, 1.0, *plant, *controller, {});
  EXPECT_TRUE(s.reached);
  EXPECT_GE(s.time_constant_min, 18.0);  // within the sample the 63 % falls in
  EXPECT_LE(s.time_constant_min, 19.0);
  // A hold shorter than that: not reached, and the hold is what it says.
  const ClosedLoopSpeed cut =
      closed_loop_speed(Eigen::VectorXd::Constant(1, 0.1), 10, 1.0, *plant, *controller, {});
  EXPECT_FALSE(cut.reached);
  EXPECT_EQ(cut.time_constant_min, 10.0);
}

struct ColaALoop {
  sim::control::ControllerFile file =
      sim::control::load_controller_file(std::string(EXCITE_CONTROL_EXAMPLES) + "/colaA.dmc.toml");
  std::unique_ptr<sim::Plant> model = sim::control::load_model(file);
  std::unique_ptr<sim::control::Controller> controller =
      sim::control::make_controller(file, *model);
  ClosedLoopOptions loop;
  ColaALoop() { set_controller(loop, file, "colaA.dmc.toml"); }
};

// colaA's textbook model G = [[0.878, −0.864], [1.082, −1.096]]/(75s + 1) under its DMC (MVs
// ±0.02 kmol/min, moves ±0.002 a minute). Along the strong output direction the DMC moves the
// MVs little and the CVs follow within minutes; along the weak one (σ_n/σ_1 ≈ 1/140) the same
// CV move asks for MV moves 140 times larger, and the move and box limits make the loop slow.
TEST(ClosedLoopSpeed, ColaAsDmcFollowsTheWeakDirectionFarSlowerThanTheStrongOne) {
  ColaALoop l;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(l.model->static_gain(), Eigen::ComputeFullU);
  const Eigen::MatrixXd W = svd.matrixU();
  // Each switch within the DMC's CV limits (±0.002) and, at steady state, the MVs' box.
  const Eigen::VectorXd strong = 0.001 * W.col(0);
  const Eigen::VectorXd weak = 0.02 * svd.singularValues()(1) * W.col(1);
  const ClosedLoopSpeed fast = closed_loop_speed(strong, 600, 1.0, *l.model, *l.controller, l.loop);
  const ClosedLoopSpeed slow = closed_loop_speed(weak, 600, 1.0, *l.model, *l.controller, l.loop);
  ASSERT_TRUE(fast.reached);
  ASSERT_TRUE(slow.reached);
  EXPECT_LE(fast.time_constant_min, 10.0);  // the open-loop τ is 75 min
  EXPECT_GE(slow.time_constant_min, 40.0);  // bounded by the MVs' limits
  EXPECT_GT(slow.time_constant_min, 5.0 * fast.time_constant_min);
}

TEST(ClosedLoopSpeed, AZeroStepOrAHoldOfOneRowIsRefusedByName) {
  ColaALoop l;
  const auto message = [&](const Eigen::VectorXd& step, int hold) {
    try {
      (void)closed_loop_speed(step, hold, 1.0, *l.model, *l.controller, l.loop);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no throw)");
  };
  EXPECT_EQ(message(Eigen::VectorXd::Zero(2), 100),
            "closed-loop speed: setpoint step of norm 0, expected a finite step that is not "
            "zero");
  EXPECT_EQ(message(Eigen::VectorXd::Constant(2, 1e-4), 1),
            "closed-loop speed: hold = 1 rows, expected at least 2");
}

}  // namespace
}  // namespace excite::host
