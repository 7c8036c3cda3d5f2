// SPDX-License-Identifier: MIT
// Controller::step allocates nothing after construction (STYLE.md practice 5): operator new
// and the malloc family counted over closed-loop samples with constraints active (DMC on
// alatiqi4x4) and for decentralised PI.
#include <gtest/gtest.h>

#include <vector>

#include "counting_malloc.hpp"
#include "counting_new.hpp"
#include "sim/control/dmc.hpp"
#include "sim/control/pi.hpp"
#include "sim/control/step_model.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::control {
namespace {

// Runs the loop; counts only the controller's steps.
void expect_no_allocation(Plant& plant, Controller& controller, const std::vector<double>& sp,
                          int samples, bool expect_constraints) {
  const auto n = static_cast<std::size_t>(plant.inputs());
  std::vector<double> applied(n, 0.0), y(static_cast<std::size_t>(plant.outputs())), u(n),
      offsets(n, 0.0);
  plant.reset(1.0);
  long news = 0, mallocs = 0;
  int active = 0;
  for (int k = 0; k < samples; ++k) {
    plant.step(applied, y);
    offsets[0] = (k / 7) % 2 ? 0.01 : -0.01;  // a known dither on MV 1
    const long n0 = excite::test::allocations();
    const long m0 = excite::test::mallocs();
    const StepReport r = controller.step(y, sp, offsets, u);
    news += excite::test::allocations() - n0;
    mallocs += excite::test::mallocs() - m0;
    active += r.active_constraints;
    for (std::size_t j = 0; j < n; ++j) applied[j] = u[j] + offsets[j];
  }
  EXPECT_EQ(news, 0) << "operator new during step()";
  if (excite::test::malloc_interposed()) {
    EXPECT_EQ(mallocs, 0) << "malloc during step()";
  }
  if (expect_constraints) {
    EXPECT_GT(active, 0) << "the QP must have worked with active constraints";
  }
}

TEST(ControllerAllocation, DmcStepWithConstraintsAllocatesNothing) {
  auto plant = make_plant("alatiqi4x4");
  DmcSettings s;
  s.prediction_horizon = 150;
  s.control_horizon = 5;
  s.mv.assign(4, MvSettings{-0.5, 0.5, 0.05, 0.1});
  s.cv.assign(4, CvSettings{});
  s.cv[1].limit_low = -0.2;
  s.cv[1].limit_high = 0.2;
  DmcController dmc(step_model(*plant, 1.0).delayed(1), s);
  expect_no_allocation(*plant, dmc, {1.0, 0.0, -0.5, 0.0}, 300, true);
}

TEST(ControllerAllocation, PiStepAllocatesNothing) {
  auto plant = make_plant("woodberry2x2");
  PiSettings s;
  s.inputs = 2;
  s.outputs = 2;
  s.loops = {PiLoop{0, 0, 0.375, 8.29}, PiLoop{1, 1, -0.075, 23.6}};
  s.mv.assign(2, MvSettings{-0.3, 0.3, 0.1, 1.0});
  PiController pi(s);
  expect_no_allocation(*plant, pi, {1.0, 0.0}, 300, false);
}

// Control: the counters see the allocations of constructing a controller.
TEST(ControllerAllocation, TheCountersSeeConstruction) {
  const long n0 = excite::test::allocations();
  PiSettings s;
  s.inputs = 1;
  s.outputs = 1;
  s.loops = {PiLoop{0, 0, 1.0, 1.0}};
  s.mv.assign(1, MvSettings{});
  PiController pi(s);
  EXPECT_GT(excite::test::allocations() - n0, 0);
}

}  // namespace
}  // namespace excite::sim::control
