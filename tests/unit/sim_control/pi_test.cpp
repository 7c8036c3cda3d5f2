// SPDX-License-Identifier: MIT
// Decentralised PI in velocity form (sim/control/pi.hpp) against hand computation, and its
// anti-windup: a clamped MV leaves its limit at the first sample the error turns.
#include <gtest/gtest.h>

#include <vector>

#include "sim/control/pi.hpp"

namespace excite::sim::control {
namespace {

// One loop, Kc = 2, τI = 4 min, T = 1 min.
PiSettings one_loop(double max = kUnlimited) {
  PiSettings s;
  s.inputs = 1;
  s.outputs = 1;
  s.loops = {PiLoop{0, 0, 2.0, 4.0}};
  s.mv = {MvSettings{}};
  s.mv[0].max = max;
  return s;
}

double step(PiController& pi, double y, double sp, double offset = 0.0) {
  double u = 0.0;
  pi.step({&y, 1}, {&sp, 1}, {&offset, 1}, {&u, 1});
  return u;
}

TEST(Pi, VelocityFormMovesAreTheHandComputedOnes) {
  PiController pi(one_loop());
  // e = 1:   Δu = 2·(1 − 0 + 0.25·1)     = 2.5   → u = 2.5
  // e = 0.5: Δu = 2·(0.5 − 1 + 0.25·0.5) = −0.75 → u = 1.75
  // e = 0.5: Δu = 2·(0 + 0.125)          = 0.25  → u = 2.0
  EXPECT_DOUBLE_EQ(step(pi, 0.0, 1.0), 2.5);
  EXPECT_DOUBLE_EQ(step(pi, 0.5, 1.0), 1.75);
  EXPECT_DOUBLE_EQ(step(pi, 0.5, 1.0), 2.0);
  pi.reset();
  EXPECT_DOUBLE_EQ(step(pi, 0.0, 1.0), 2.5);
}

TEST(Pi, AClampedMvDoesNotWindUp) {
  PiController pi(one_loop(1.0));
  for (int k = 0; k < 10; ++k) {
    EXPECT_DOUBLE_EQ(step(pi, 0.0, 1.0), 1.0);  // e = 1 held: the MV sits on max = 1
    EXPECT_EQ(pi.mv_status()[0], MvStatus::clamped_high);
  }
  // The error turns to −0.1: Δu = 2·(−0.1 − 1 − 0.025) = −2.25 from the clamped u = 1.
  // (A position-form PI without anti-windup would ask 2·(−0.1 + 0.25·9.9) = 4.75 and stay
  // on its limit.)
  EXPECT_DOUBLE_EQ(step(pi, 1.1, 1.0), 1.0 - 2.25);
  EXPECT_EQ(pi.mv_status()[0], MvStatus::ok);
}

TEST(Pi, MoveLimitsAndTheBoxOfTheAppliedMv) {
  PiSettings s = one_loop(1.0);
  s.mv[0].max_move = 0.5;
  PiController pi(s);
  EXPECT_DOUBLE_EQ(step(pi, 0.0, 1.0), 0.5);
  EXPECT_EQ(pi.mv_status()[0], MvStatus::move_limited);
  // With an offset of 0.8 on the MV the controller's own output may reach only 0.2.
  EXPECT_DOUBLE_EQ(step(pi, 0.0, 1.0, 0.8), 0.2);
  EXPECT_EQ(pi.mv_status()[0], MvStatus::clamped_high);
}

TEST(Pi, AnUnpairedMvStaysAtZeroAndTheLoopsAreIndependent) {
  PiSettings s;
  s.inputs = 3;
  s.outputs = 2;
  s.loops = {PiLoop{1, 0, 2.0, 4.0}, PiLoop{0, 2, -1.0, 2.0}};
  s.mv.assign(3, MvSettings{});
  PiController pi(s);
  const double y[2] = {0.0, 0.0}, sp[2] = {1.0, 1.0}, offset[3] = {0, 0, 0};
  double u[3];
  EXPECT_EQ(pi.step(y, sp, offset, u).status, StepStatus::ok);
  EXPECT_DOUBLE_EQ(u[0], 2.5);   // CV 2 → MV 1
  EXPECT_DOUBLE_EQ(u[1], 0.0);   // unpaired
  EXPECT_DOUBLE_EQ(u[2], -1.5);  // CV 1 → MV 3: −1·(1 + 0.5)
}

TEST(Pi, RefusesPairingsByName) {
  const auto message = [](PiSettings s) {
    try {
      PiController pi(std::move(s));
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(accepted)");
  };
  PiSettings s = one_loop();
  s.loops.push_back(PiLoop{0, 0, 1.0, 1.0});
  EXPECT_EQ(message(s), "pairing[1].cv = 1, expected a CV in no other pairing");
  s = one_loop();
  s.loops[0].integral_min = 0.0;
  EXPECT_EQ(message(s), "pairing[0].ti_min = 0, expected a finite integral time > 0 minutes");
  s = one_loop();
  s.loops[0].mv = 3;
  EXPECT_EQ(message(s), "pairing[0].mv = 4, expected an MV 1..1");
}

}  // namespace
}  // namespace excite::sim::control
