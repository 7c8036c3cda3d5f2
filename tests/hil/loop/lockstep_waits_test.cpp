// SPDX-License-Identifier: MIT
// Issue 39 §2, with the real gateway and the real plant server over a real socket: in
// lock-step the waits do not stretch with the plan's period. The loop runs at the plan's own
// sample time (1 min: no gateway.period_s, as `excite loop-config` writes it and README.md's
// loop runs); excite-plant freezes itself after 300 requests (--freeze-ms: nothing read or
// answered), and the gateway's response timeout is 100 ms.
//  - a retry after a failed exchange waits 250 ms on the real clock: over a 2 s freeze the
//    gateway fails 4 … 10 exchanges and completes (before: it waited the 60 s period after
//    the first failure — one failed exchange, and a ~1 s run took 61 s);
//  - suspend_timeout_s and confirm_timeout_s are real time: a peer frozen for good aborts
//    the run 1.5 s after the suspension and gives up confirming 1.5 s later, exit 10 (before:
//    one tick of 60 s each, each retry 60 s: minutes);
//  - `abort` on stdin and SIGTERM during the retries are acted on at the next retry.
// Counts, not times, are asserted; the waits below are hang guards far beyond what the
// gateway needs (the previous code needed minutes, so it ran into them).
#include <signal.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

std::size_t rows_in(const runlog::RunLog& log, runlog::RunState state) {
  std::size_t n = 0;
  for (const runlog::RunState s : log.state) n += s == state ? 1U : 0U;
  return n;
}

/// The number after `key` in `text` (the summary's counts), or -1.
long long count_after(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  return at == std::string::npos ? -1 : std::stoll(text.substr(at + key.size()));
}

class LockstepWaits : public LoopTest {
 protected:
  /// The loop at the plan's sample time; the plant freezes for `freeze_ms` after 300
  /// requests; `gateway_keys` are added to gateway.toml's [gateway] section.
  void start(int freeze_ms, const std::string& gateway_keys) {
    start_loop(kPlant, "--input-range 2",
               {"--clock", "lockstep", "--watchdog-s", "0", "--freeze-ms",
                std::to_string(freeze_ms), "--freeze-after", "300"});
    plan_ = design(kPlant, "prbsUnc");
    const fs::path p = path("gateway.toml");
    std::string text = slurp(p);
    const auto replace = [&text](const std::string& from, const std::string& to) {
      const std::size_t at = text.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      text.replace(at, from.size(), to);
    };
    replace("comm_fail_limit = 3", "comm_fail_limit = 3\n" + gateway_keys);
    replace("response_timeout_ms = 1000", "response_timeout_ms = 100");
    std::ofstream(p) << text;
  }

  static bool wait_for(GatewayProcess& gw, const std::string& text) {
    for (int i = 0; i < 2000; ++i) {
      if (gw.err().find(text) != std::string::npos) return true;
      std::this_thread::sleep_for(5ms);
    }
    return false;
  }

  void kill_plant() { plant_->stop(SIGKILL); }

  fs::path plan_;
};

// GIVEN the plant frozen 2 s mid-run THEN the gateway retries every 250 ms (plus the 100 ms
// response timeout): 4 … 10 failed exchanges, and the run completes.
TEST_F(LockstepWaits, AFrozenPeerIsRetriedEveryPacingIntervalNotEveryPeriod) {
  start(2000, "");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 0) << err;
  const long long failed = count_after(err, "failed exchanges ");
  EXPECT_GE(failed, 4) << err;
  EXPECT_LE(failed, 10) << err;
  EXPECT_GE(count_after(err, "retries paced "), failed - 1) << err;
  kill_plant();
}

// GIVEN the plant frozen for good, suspend_timeout_s = 1.5 and confirm_timeout_s = 1.5
// THEN aborted on the suspension timeout after 3 … 8 paced retries, then 3 … 8 more while
// confirming, and `safe, unconfirmed` naming 1.5 s: exit 10.
TEST_F(LockstepWaits, TheSuspensionAndConfirmationTimeoutsAreRealTime) {
  start(20000, "suspend_timeout_s = 1.5\nconfirm_timeout_s = 1.5");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 10) << err;
  EXPECT_NE(err.find("(aborted on suspension timeout)"), std::string::npos) << err;
  EXPECT_NE(err.find("within gateway.confirm_timeout_s = 1.5 s"), std::string::npos) << err;
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  const std::size_t suspended = rows_in(log, runlog::RunState::suspended);
  const std::size_t returning = rows_in(log, runlog::RunState::returning);
  EXPECT_GE(suspended, 3U) << err;
  EXPECT_LE(suspended, 8U) << err;
  EXPECT_GE(returning, 3U) << err;
  EXPECT_LE(returning, 8U) << err;
  kill_plant();
}

// GIVEN the plant frozen for good and no suspension timeout WHEN the operator aborts on stdin
// during the retries THEN it is acted on: aborted by operator, unconfirmed after 1 s, exit 10.
TEST_F(LockstepWaits, AnAbortDuringTheRetriesIsActedOn) {
  start(20000, "confirm_timeout_s = 1");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  ASSERT_TRUE(wait_for(*gw, "running -> suspended")) << gw->err();
  gw->send_line("abort");
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 10) << err;
  EXPECT_NE(err.find("(aborted by operator)"), std::string::npos) << err;
  kill_plant();
}

// The same with SIGTERM.
TEST_F(LockstepWaits, ASigtermDuringTheRetriesIsActedOn) {
  start(20000, "confirm_timeout_s = 1");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  ASSERT_TRUE(wait_for(*gw, "running -> suspended")) << gw->err();
  gw->signal(SIGTERM);
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 10) << err;
  EXPECT_NE(err.find("(aborted by operator)"), std::string::npos) << err;
  kill_plant();
}

}  // namespace
}  // namespace excite::test
