// SPDX-License-Identifier: MIT
// Issue 28 item 2, with the real gateway and the real plant server over a real socket: safe
// means confirmed and held, however long the peer was frozen. The plant's own watchdog is
// off (--watchdog-s 0), so only the gateway can bring it back.
//  - excite-plant frozen 10 s mid-run by its own fault option (--freeze-ms, nothing read or
//    answered), the gateway at 20 ms ticks with suspend_timeout_s = 3: the gateway aborts,
//    keeps confirming for confirm_timeout_s (60 s by default), sees the plant come back,
//    undoes the stale write the plant applies on waking, and ends confirmed (exit 6); the
//    plant's own log is excited at most 1 s of samples after it runs again and ends at its
//    baseline (before: exit 10 "safe, unconfirmed" while the plant was still frozen, and the
//    plant then held the stale excitation for good);
//  - the same with the plant SIGSTOPped and SIGCONTed.
#include <signal.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

constexpr std::size_t kSamplesPerSecond = 50;  // 20 ms ticks, one lock-step sample each

bool at_baseline(const runlog::RunLog& plant, std::size_t row) {
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    if (std::abs(plant.du[i][row]) > 1e-6) return false;
  }
  return true;
}

class Confirm : public LoopTest {
 protected:
  void start(std::vector<std::string> plant_args) {
    plant_args.insert(plant_args.begin(), {"--clock", "lockstep", "--watchdog-s", "0"});
    start_loop(kPlant, "--input-range 2 --period-s 0.02", plant_args);
    plan_ = design(kPlant, "prbsUnc");
    const fs::path p = path("gateway.toml");
    std::string text = slurp(p);
    const std::string from = "comm_fail_limit = 3";
    text.replace(text.find(from), from.size(), "comm_fail_limit = 3\nsuspend_timeout_s = 3");
    std::ofstream(p) << text;
  }

  void expect_confirmed_abort(const std::string& err, int rc) {
    EXPECT_EQ(rc, 6) << err;
    EXPECT_NE(err.find("aborted on suspension timeout"), std::string::npos) << err;
    EXPECT_NE(err.find("excite-gateway: safe after"), std::string::npos) << err;
    EXPECT_NE(err.find("; stale writes undone "), std::string::npos) << err;
  }

  fs::path plan_;
};

// The plant freezes itself after 900 requests (about 6 s of the run) for 10 s.
TEST_F(Confirm, APeerFrozenLongerThanTheSuspendTimeoutEndsConfirmedAtItsBaseline) {
  start({"--freeze-ms", "10000", "--freeze-after", "900"});
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(90s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  expect_confirmed_abort(err, *rc);

  const runlog::RunLog plant = stop_plant_and_read_its_log();
  const std::string plant_err = plant_->stderr_text();
  const std::size_t at = plant_err.find(" at sample ");
  ASSERT_NE(at, std::string::npos) << plant_err;
  const std::size_t frozen_at = std::stoul(plant_err.substr(at + 11));
  ASSERT_LT(frozen_at + 1, plant.rows());
  ASSERT_FALSE(at_baseline(plant, frozen_at - 1)) << "not excited before the freeze";
  // After it runs again: excited for at most 1 s of samples, then at its baseline for good.
  std::size_t excited_after = 0;
  for (std::size_t k = frozen_at; k < plant.rows(); ++k)
    excited_after += at_baseline(plant, k) ? 0U : 1U;
  EXPECT_LE(excited_after, kSamplesPerSecond) << err;
  const std::size_t undone = err.find("stale writes undone ");
  std::printf(
      "[ measured ] frozen at plant sample %zu; %zu excited samples after it (at most "
      "%zu); stale writes undone %s\n",
      frozen_at, excited_after, kSamplesPerSecond,
      undone == std::string::npos ? "?" : err.substr(undone + 20, 3).c_str());
  EXPECT_TRUE(at_baseline(plant, plant.rows() - 1)) << "the plant was left excited";
}

// The same freeze by SIGSTOP / SIGCONT of the plant's process.
TEST_F(Confirm, APeerStoppedLongerThanTheSuspendTimeoutEndsConfirmedAtItsBaseline) {
  start({});
  auto gw = start_gateway(plan_, {"--start"});
  std::this_thread::sleep_for(6s);
  plant_->signal(SIGSTOP);
  std::this_thread::sleep_for(10s);
  plant_->signal(SIGCONT);
  const auto rc = gw->wait(90s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  expect_confirmed_abort(gw->err(), *rc);
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  ASSERT_GT(plant.rows(), 0U);
  EXPECT_TRUE(at_baseline(plant, plant.rows() - 1)) << "the plant was left excited";
}

}  // namespace
}  // namespace excite::test
