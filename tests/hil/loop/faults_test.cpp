// SPDX-License-Identifier: MIT
// Faults on purpose, with the real gateway and the real plant server: each test asserts
// where the plant ends up (its own run log: every input inside the configured limits, back
// at the baseline at the end), the gateway's exit code, and that the gateway's log marks
// the fault.
#include <arpa/inet.h>
#include <modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <fstream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "../gateway/killed_log.hpp"
#include "firmware/runlog/format.hpp"
#include "limits.hpp"
#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

// Every input the plant received stayed inside the limits, and the last one is the
// baseline (within the float32 register's rounding).
void expect_plant_inside_limits_and_back_at_baseline(const runlog::RunLog& plant) {
  ASSERT_GT(plant.rows(), 0U);
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    EXPECT_LE(max_abs(plant.du[i]), kInputRange * (1 + 1e-6)) << plant.input_names[i];
    EXPECT_LE(std::abs(plant.du[i].back()), 1e-6 * (1 + max_abs(plant.u[i])))
        << plant.input_names[i] << " is not back at its baseline";
  }
}

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

class Faults : public LoopTest {
 protected:
  // The loop for woodberry2x2 with a real-time gateway ticking every 5 ms (so faults
  // happen in the middle of a run) and a lock-step plant.
  void start(const std::string& extra_config = "",
             const std::vector<std::string>& plant_faults = {}) {
    std::vector<std::string> plant_args = {"--clock", "lockstep"};
    plant_args.insert(plant_args.end(), plant_faults.begin(), plant_faults.end());
    port_ = start_loop(kPlant, "--input-range 2 --period-s 0.005 " + extra_config, plant_args);
    plan_ = design(kPlant, "prbsUnc");
  }

  // Rewrites one line of gateway.toml (a key loop-config has no option for).
  void edit_gateway(const std::string& from, const std::string& to) {
    const fs::path p = path("gateway.toml");
    const std::string text = slurp(p);
    ASSERT_NE(text.find(from), std::string::npos) << from;
    std::ofstream(p) << replace(text, from, to);
  }

  // Waits until the plant server has logged `samples` samples.
  bool wait_for_plant_samples(std::size_t samples, std::chrono::milliseconds timeout = 20s) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      std::size_t lines = 0;
      std::ifstream in(path("plant.csv"));
      for (std::string line; std::getline(in, line);)
        lines += line.empty() || line[0] == '#' ? 0U : 1U;
      if (lines > samples) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }

  // Hides the free function of the same name in this fixture's tests: the same checks, and
  // every u the plant received inside the [min, max] gateway.toml configures (limits.hpp).
  void expect_plant_inside_limits_and_back_at_baseline(const runlog::RunLog& plant) {
    test::expect_plant_inside_limits_and_back_at_baseline(plant);
    expect_plant_inside_configured_limits(plant, configured_limits(path("gateway.toml")));
  }

  std::uint16_t port_ = 0;
  fs::path plan_;
};

TEST_F(Faults, ConnectionRefusedAtStartExitsFourAndCreatesNoLog) {
  // A port nobody listens on: bound, read, closed.
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  socklen_t len = sizeof a;
  getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
  close(s);
  loop_config(kPlant, ntohs(a.sin_port), "--input-range 2");
  auto gw = start_gateway(design(kPlant, "prbsUnc"), {"--start"});
  EXPECT_EQ(gw->wait(20s).value_or(-1), 4) << gw->err();
  EXPECT_NE(gw->err().find("Connection refused"), std::string::npos) << gw->err();
  EXPECT_FALSE(fs::exists(path("gw.csv")));
}

TEST_F(Faults, PlantKilledMidRunAndRestartedIsACommLossAndTheRunEndsAtBaseline) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples(150));
  // GIVEN a run in progress; WHEN the plant server dies and comes back on the same port
  plant_->stop(SIGKILL);
  std::this_thread::sleep_for(300ms);
  start_plant({"--clock", "lockstep"}, port_, "plant2.csv");
  // THEN the gateway holds through the loss, reconnects and finishes; the restarted plant
  // never sees an input outside the limits and ends at the baseline.
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  EXPECT_GT(rows_with(log, runlog::kCommLost), 0U) << "the loss is not marked in the log";
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log("plant2.csv"));
}

TEST_F(Faults, RepliesDelayedPastTheTimeoutAreACommLossThenTheRunRecovers) {
  start("", {"--stall-requests", "4", "--stall-ms", "300", "--faults-after", "600"});
  edit_gateway("response_timeout_ms = 1000", "response_timeout_ms = 100");
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  EXPECT_GT(rows_with(log, runlog::kCommLost), 0U);
  EXPECT_NE(gw->err().find("communication lost"), std::string::npos) << gw->err();
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log());
}

TEST_F(Faults, ExceptionRepliesAreFailedExchangesAndAreMarked) {
  start("", {"--exception-requests", "6", "--faults-after", "600"});
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const std::string err = gw->err();
  const auto at = err.find("failed exchanges ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_GE(std::stoul(err.substr(at + 17)), 3U) << err;
  EXPECT_GT(rows_with(read_log_or_fail(path("gw.csv")), runlog::kCommLost), 0U);
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log());
}

// A peer that answers every request with garbage, and remembers which function codes it
// was asked for.
class GarbagePeer {
 public:
  GarbagePeer() {
    listen_fd_ = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len);
    port_ = ntohs(a.sin_port);
    listen(listen_fd_, 4);
    thread_ = std::thread([this] { serve(); });
  }
  ~GarbagePeer() {
    stop_ = true;
    shutdown(listen_fd_, SHUT_RDWR);
    close(listen_fd_);
    thread_.join();
  }
  std::uint16_t port() const { return port_; }
  std::set<int> function_codes() {
    std::lock_guard<std::mutex> lock(mutex_);
    return codes_;
  }

 private:
  void serve() {
    while (!stop_) {
      const int c = accept(listen_fd_, nullptr, nullptr);
      if (c < 0) return;
      timeval tv{0, 200000};
      setsockopt(c, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
      unsigned char buf[260];
      while (!stop_) {
        const ssize_t n = recv(c, buf, sizeof buf, 0);
        if (n == 0) break;
        if (n < 0) continue;
        if (n >= 8) {
          std::lock_guard<std::mutex> lock(mutex_);
          codes_.insert(buf[7]);
        }
        // A well-formed header with a length that lies and a payload of noise.
        const unsigned char reply[] = {buf[0], buf[1], 0, 0, 0, 9, 1, 0x03, 0xFF, 0x13, 0x37};
        send(c, reply, sizeof reply, MSG_NOSIGNAL);
      }
      close(c);
    }
  }
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex mutex_;
  std::set<int> codes_;
};

TEST_F(Faults, MalformedRepliesAtStartAreRefusedBeforeAnythingIsWritten) {
  GarbagePeer peer;
  loop_config(kPlant, peer.port(), "--input-range 2");
  auto gw = start_gateway(design(kPlant, "prbsUnc"), {"--start"});
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 5) << gw->err();  // refused to arm: the first read failed
  const std::set<int> asked = peer.function_codes();
  EXPECT_FALSE(asked.empty()) << "the gateway never asked";
  EXPECT_EQ(asked.count(16), 0U) << "the gateway wrote to a peer whose replies are garbage";
  EXPECT_EQ(asked.count(6), 0U);
}

TEST_F(Faults, ControlledVariableOutsideItsTestLimitsSuspendsThenResumes) {
  // Test limits at ±0.5 around each output's baseline: the PRBS drives woodberry2x2's
  // outputs (gains up to 19) past them, so the gateway must suspend, return the inputs to
  // the baseline, and resume once the outputs are back inside the hysteresis band.
  start("--output-range 0.5");
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples(400, 60s));
  gw->signal(SIGTERM);
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 6) << gw->err();
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  std::size_t resumed = 0;
  for (std::size_t r = 1; r < log.rows(); ++r) {
    const bool was = (log.flags[r - 1] & runlog::kSuspended) != 0;
    const bool is = (log.flags[r] & runlog::kSuspended) != 0;
    resumed += was && !is ? 1 : 0;
  }
  EXPECT_GT(rows_with(log, runlog::kSuspended), 0U) << "never suspended";
  EXPECT_GT(resumed, 0U) << "never resumed";
  // While suspended the inputs sit at the baseline.
  for (std::size_t r = 0; r < log.rows(); ++r) {
    if ((log.flags[r] & runlog::kSuspended) == 0) continue;
    for (const auto& du : log.du) EXPECT_EQ(du[r], 0.0) << "row " << r;
  }
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log());
}

TEST_F(Faults, OperatorAbortOverTheCommandRegisterReturnsThePlantToBaseline) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples(100));
  // An operator panel writes 4 (abort) to the command register.
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port_);
  ASSERT_NE(ctx, nullptr);
  ASSERT_EQ(modbus_connect(ctx), 0);
  EXPECT_EQ(modbus_write_register(ctx, 301, 4), 1) << modbus_strerror(errno);
  modbus_close(ctx);
  modbus_free(ctx);
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 6) << gw->err();
  EXPECT_NE(gw->err().find("aborted"), std::string::npos) << gw->err();
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log());
}

TEST_F(Faults, SigtermRampsOutAndThePlantEndsAtBaseline) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples(100));
  gw->signal(SIGTERM);
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 6) << gw->err();
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  EXPECT_LT(log.rows(), 900U) << "the run was not cut short";
  expect_plant_inside_limits_and_back_at_baseline(stop_plant_and_read_its_log());
}

TEST_F(Faults, SigkillLeavesAValidLogAndNothingOutsideTheLimits) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples(100));
  gw->signal(SIGKILL);
  ASSERT_EQ(gw->wait(10s).value_or(-1), 128 + SIGKILL);
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  EXPECT_GE(log.rows(), 50U);
  // Every tick is a row, except grid points a late tick skipped (run-log v2: the row after
  // them is flagged skipped and k jumps over them; the reader checked that k and t agree).
  std::uint64_t skipped = 0;
  for (std::size_t r = 1; r < log.rows(); ++r) skipped += log.k[r] - log.k[r - 1] - 1;
  EXPECT_EQ(log.k.back(), log.rows() - 1 + skipped);
  // Within the plant's watchdog time it holds the last setpoint, which is inside the limits
  // (tests/hil/loop/watchdog_test checks what happens after it).
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  EXPECT_EQ(expect_last_row_whole(path("gw.csv")), log.rows());
  expect_logged_rows_reached_the_plant(log, plant);
  expect_plant_inside_configured_limits(plant, configured_limits(path("gateway.toml")));
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    EXPECT_LE(max_abs(plant.du[i]), kInputRange * (1 + 1e-6)) << plant.input_names[i];
  }
}

}  // namespace
}  // namespace excite::test
