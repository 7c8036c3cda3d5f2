// SPDX-License-Identifier: MIT
// Verified writes (readbacks compared with the setpoints written, within the register's
// resolution, after the configured lag) and the confirmed safe state.
#include <cmath>
#include <functional>

#include "engine_fixture.hpp"

namespace excite::engine::testing {
namespace {

EngineConfig verified_config() {
  EngineConfig c = small_config();
  c.verify_readbacks = true;
  c.readback_lag_ticks = 1;
  c.readback_mismatch_limit = 3;
  for (std::uint32_t i = 0; i < 2; ++i) c.input[i].readback_rel_tol = std::ldexp(1.0, -23);
  return c;
}

class VerifyTest : public EngineTest {
 protected:
  // One tick through a field whose readback of setpoint 0 is `corrupt0(written)` and whose
  // readbacks lag `delay` ticks behind the writes (0: the same exchange).
  void field_tick() {
    const TickOutput& out = engine_.compute();
    last_ = out;
    if (out.write) {
      history_.push_back({out.setpoint[0], out.setpoint[1]});
      const auto& seen =
          history_.size() > delay_ ? history_[history_.size() - 1 - delay_] : history_.front();
      field_.values[kRb0] = corrupt0_ ? corrupt0_(seen[0]) : seen[0];
      field_.values[kRb1] = seen[1];
      field_.values[kEcho] = out.heartbeat;
    }
    engine_.observe(true, field_.values);
  }
  void field_ticks(int n) {
    for (int i = 0; i < n; ++i) field_tick();
  }
  void arm_verified(const EngineConfig& c) {
    configure(c);
    arm();
    history_.assign(delay_ + 1, {engine_.baseline(0), engine_.baseline(1)});  // written at arm
    // the field takes the baseline written at arm and reads it back
    field_.values[kRb0] = corrupt0_ ? corrupt0_(engine_.baseline(0)) : engine_.baseline(0);
    arm_status_ = engine_.verify_arm(field_.values);
  }
  std::function<double(double)> corrupt0_;
  std::size_t delay_ = 0;
  std::vector<std::array<double, 2>> history_;
  Status arm_status_;
};

TEST_F(VerifyTest, Float32AgreesWithinTwoToTheMinus23Relative) {
  configure(verified_config());
  const double w = 40.0;
  EXPECT_TRUE(engine_.readback_agrees(0, w, static_cast<float>(w + 1e-6)));  // float rounding
  EXPECT_TRUE(engine_.readback_agrees(0, w, w * (1.0 + std::ldexp(1.0, -23))));
  EXPECT_FALSE(engine_.readback_agrees(0, w, w * (1.0 + std::ldexp(1.0, -21))));
  EXPECT_FALSE(engine_.readback_agrees(0, w, 6.7e33));
  EXPECT_FALSE(engine_.readback_agrees(0, w, std::nan("")));
}

TEST_F(VerifyTest, ScaledIntegerAgreesWithinOneRawStep) {
  EngineConfig c = verified_config();
  c.input[0].readback_rel_tol = 0.0;
  c.input[0].readback_abs_tol = 0.1;  // one raw step, engineering units
  configure(c);
  EXPECT_TRUE(engine_.readback_agrees(0, 40.0, 40.05));  // rounded to the nearest step
  EXPECT_TRUE(engine_.readback_agrees(0, 40.0, 39.95));
  EXPECT_FALSE(engine_.readback_agrees(0, 40.0, 40.2));
}

TEST_F(VerifyTest, ArmRefusesAReadbackThatDisagreesWithTheBaseline) {
  corrupt0_ = [](double) { return 6.7e33; };
  arm_verified(verified_config());
  EXPECT_FALSE(arm_status_);
  EXPECT_EQ(engine_.state(), State::configured);
  const ReadbackFault& f = engine_.readback_fault();
  ASSERT_TRUE(f.valid);
  EXPECT_TRUE(f.at_arm);
  EXPECT_EQ(f.input, 0U);
  EXPECT_EQ(f.written, 40.0);
  EXPECT_EQ(f.read, 6.7e33);
  EXPECT_FALSE(engine_.compute().write);  // refused: nothing more is written
}

TEST_F(VerifyTest, ArmAcceptsAnEchoedBaseline) {
  arm_verified(verified_config());
  EXPECT_TRUE(arm_status_) << arm_status_.message();
  EXPECT_EQ(engine_.state(), State::armed);
  EXPECT_FALSE(engine_.readback_fault().valid);
}

TEST_F(VerifyTest, MismatchesUpToTheLimitAreToleratedThenAFaultStopsTheExcitation) {
  arm_verified(verified_config());
  engine_.command(Command::start);
  field_ticks(2);
  corrupt0_ = [](double w) { return w + 1.0; };
  field_ticks(3);  // 3 mismatches = the limit: no fault yet
  EXPECT_EQ(engine_.state(), State::running);
  EXPECT_FALSE(engine_.readback_fault().valid);
  field_tick();  // the 4th in a row: fault
  EXPECT_EQ(engine_.state(), State::aborted);
  EXPECT_EQ(engine_.outcome(), Outcome::readback_fault);
  const ReadbackFault& f = engine_.readback_fault();
  ASSERT_TRUE(f.valid);
  EXPECT_FALSE(f.at_arm);
  EXPECT_EQ(f.input, 0U);
  EXPECT_EQ(f.written, 40.0 + 6.0);  // row 5 (0-based) of channel 0 = +6
  EXPECT_EQ(f.read, 40.0 + 7.0);
  EXPECT_EQ(engine_.readback_mismatches(), 4U);
}

TEST_F(VerifyTest, AStreakBrokenByOneGoodReadingDoesNotFault) {
  arm_verified(verified_config());
  engine_.command(Command::start);
  int n = 0;
  corrupt0_ = [&n](double w) { return ++n % 4 == 0 ? w : w + 1.0; };  // 3 bad, 1 good
  field_ticks(7);
  EXPECT_FALSE(engine_.readback_fault().valid);
  EXPECT_EQ(engine_.readback_mismatches(), 6U);
}

TEST_F(VerifyTest, AFaultThatClearsAtBaselineEndsConfirmedSafe) {
  arm_verified(verified_config());
  engine_.command(Command::start);
  field_ticks(1);
  corrupt0_ = [this](double w) { return w == engine_.baseline(0) ? w : -w; };
  field_ticks(4);
  EXPECT_EQ(engine_.outcome(), Outcome::readback_fault);
  field_ticks(3);
  EXPECT_EQ(engine_.state(), State::safe);  // baseline written and read back
  EXPECT_EQ(last_.setpoint[0], 40.0);
}

TEST_F(VerifyTest, ABaselineNeverReadBackEndsSafeUnconfirmed) {
  EngineConfig c = verified_config();
  c.suspend_timeout_ticks = 10;  // the confirmation window: max(10, lag + limit + 1)
  arm_verified(c);
  engine_.command(Command::start);
  field_ticks(1);
  corrupt0_ = [](double w) { return -w; };
  field_ticks(4);
  EXPECT_EQ(engine_.state(), State::aborted);
  int guard = 0;
  while (!finished(engine_.state()) && guard++ < 100) field_tick();
  EXPECT_EQ(engine_.state(), State::safe_unconfirmed);
  EXPECT_STREQ(to_string(engine_.state()), "safe, unconfirmed");
  EXPECT_GE(guard, 10);
  EXPECT_LT(guard, 20);
}

TEST_F(VerifyTest, ALagOfTwoComparesWithThePreviousWrite) {
  delay_ = 1;  // the field reports last tick's setpoints
  EngineConfig lag1 = verified_config();
  arm_verified(lag1);
  engine_.command(Command::start);
  field_ticks(5);
  EXPECT_EQ(engine_.outcome(), Outcome::readback_fault) << "lag 1 against a field one behind";

  engine_ = Engine{};
  EngineConfig lag2 = verified_config();
  lag2.readback_lag_ticks = 2;
  arm_verified(lag2);
  engine_.command(Command::start);
  int guard = 0;
  while (!finished(engine_.state()) && guard++ < 100) field_tick();
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(engine_.outcome(), Outcome::completed);
  EXPECT_EQ(engine_.readback_mismatches(), 0U);
}

// Issue 28 item 2: with confirmation on, safe needs two readbacks of the baseline at least
// confirm_hold_ticks apart; a stale value at the baseline is undone and counted, not a fault.
TEST_F(VerifyTest, ConfirmationNeedsTwoReadbacksAHoldApartAndCountsAStaleWrite) {
  EngineConfig c = verified_config();
  c.confirm_timeout_ticks = 50;
  c.confirm_hold_ticks = 3;
  arm_verified(c);
  engine_.command(Command::start);
  field_ticks(2);
  engine_.command(Command::abort);
  field_tick();  // aborted
  field_tick();  // returning, output at the baseline, first readback
  EXPECT_EQ(engine_.state(), State::returning);
  field_ticks(2);  // 2 ticks after the first: not yet the hold of 3
  EXPECT_EQ(engine_.state(), State::returning);
  // The device applies a stale excitation for 5 ticks (a write in flight when it froze).
  corrupt0_ = [](double w) { return w + 0.5; };
  field_ticks(5);
  EXPECT_EQ(engine_.state(), State::returning);
  EXPECT_EQ(engine_.stale_writes_undone(), 1U);
  EXPECT_FALSE(engine_.readback_fault().valid) << "a stale write while returning is no fault";
  corrupt0_ = nullptr;
  field_ticks(3);  // first readback again, then 2 ticks
  EXPECT_EQ(engine_.state(), State::returning);
  field_tick();  // the hold of 3 after the first
  EXPECT_EQ(engine_.state(), State::safe);
  EXPECT_EQ(engine_.outcome(), Outcome::aborted_by_operator);
}

TEST_F(VerifyTest, ConfirmationGivesUpAfterItsTimeoutOnTheClock) {
  EngineConfig c = verified_config();
  c.confirm_timeout_ticks = 20;
  c.confirm_hold_ticks = 2;
  arm_verified(c);
  engine_.command(Command::abort);
  field_tick();
  corrupt0_ = [](double w) { return w + 0.5; };  // never reads back the baseline
  int guard = 0;
  while (!finished(engine_.state()) && guard++ < 100) field_tick();
  EXPECT_EQ(engine_.state(), State::safe_unconfirmed);
  EXPECT_GE(guard, 19);
  EXPECT_LE(guard, 21);
}

TEST_F(VerifyTest, ConfigRefusesALagOutOfRange) {
  EngineConfig c = verified_config();
  c.readback_lag_ticks = 0;
  EXPECT_FALSE(validate(c));
  c.readback_lag_ticks = kMaxReadbackLag + 1;
  const Status s = validate(c);
  EXPECT_FALSE(s);
  EXPECT_NE(std::string(s.message()).find("readback_lag_ticks"), std::string::npos);
}

}  // namespace
}  // namespace excite::engine::testing
