// SPDX-License-Identifier: MIT
// The real excite-gateway process against a real Modbus TCP peer on 127.0.0.1 (libmodbus
// FaultServer in this process, STYLE.md practice 9): the case-study plan from
// `excite design`, every exit path, operator commands, faults, and bad input.
//
// The peer: setpoints in holding registers 100..107 (float32 CDAB) and the heartbeat at
// 108; the gateway reads them back with FC03 (the baseline); outputs in input registers
// 200..207 (float32 CDAB); a peer thread echoes the heartbeat into input register 300;
// input register 301 is the operator command register.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "firmware/runlog/format.hpp"
#include "firmware/runlog/reader.hpp"
#include "tests/hil/gateway/gateway_process.hpp"
#include "tests/hil/hal_modbus/fault_server.hpp"

namespace excite::test {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

constexpr double kU0[4] = {50.0, 60.0, 70.0, 80.0};
constexpr double kY0 = 0.5;

void put_float(FaultServer& s, bool holding, int address, float value) {
  const auto bits = std::bit_cast<std::uint32_t>(value);  // CDAB: low word first
  const auto lo = static_cast<std::uint16_t>(bits & 0xFFFFU);
  const auto hi = static_cast<std::uint16_t>(bits >> 16U);
  if (holding) {
    s.set_holding(address, lo);
    s.set_holding(address + 1, hi);
  } else {
    s.set_input(address, lo);
    s.set_input(address + 1, hi);
  }
}

float holding_float(FaultServer& s, int address) {
  const std::uint32_t bits = static_cast<std::uint32_t>(s.holding(address)) |
                             (static_cast<std::uint32_t>(s.holding(address + 1)) << 16U);
  return std::bit_cast<float>(bits);
}

std::string config_text(std::uint16_t port, int setpoints = 4,
                        const std::string& extra_setpoint = "",
                        const std::string& word_order = "CDAB") {
  std::ostringstream t;
  t << R"([gateway]
plant = "loopback Modbus TCP peer"
period_s = 0.002
ramp_s = 0.01
resume_dwell_s = 0.04
suspend_timeout_s = 2.0
comm_fail_limit = 3
comm_loss = "hold"
heartbeat_max_lag_s = 0.2
log_ring = 16384
realtime_priority = 0

[device]
transport = "tcp"
host = "127.0.0.1"
port = )"
    << port << R"(
unit_id = 1
response_timeout_ms = 50

[map]
heartbeat_address = 108
)";
  const char* names[] = {"L", "V", "S", "F"};
  for (int i = 0; i < setpoints; ++i) {
    t << "\n[[setpoints]]\nname = \"" << names[i] << "\"\nunit = \"kmol/min\"\naddress = "
      << (i == 1 && !extra_setpoint.empty() ? extra_setpoint : std::to_string(100 + 2 * i))
      << "\ntype = \"float32\"\nword_order = \"" << word_order << "\"\nmin = " << kU0[i] - 10
      << "\nmax = " << kU0[i] + 10 << "\nmax_move = 1.0\nreadback = \"" << names[i] << "_sp\"\n";
  }
  const char* outputs[] = {"xD", "xS", "xB", "T"};
  for (int j = 0; j < 4; ++j) {
    t << "\n[[values]]\nname = \"" << outputs[j] << "\"\naddress = " << 200 + 2 * j
      << "\nfunction_code = 4\ntype = \"float32\"\nword_order = \"CDAB\"\ntest_low = " << kY0 - 5
      << "\ntest_high = " << kY0 + 5 << "\nhysteresis = 0.5\n";
  }
  for (int i = 0; i < setpoints; ++i) {
    t << "\n[[values]]\nname = \"" << names[i]
      << "_sp\"\nrole = \"readback\"\naddress = " << 100 + 2 * i
      << "\nfunction_code = 3\ntype = \"float32\"\nword_order = \"CDAB\"\n";
  }
  t << R"(
[[values]]
name = "hb_echo"
role = "heartbeat_echo"
address = 300
function_code = 4
type = "uint16"
eng_min = 0
eng_max = 65535

[[values]]
name = "command"
role = "command"
address = 301
function_code = 4
type = "uint16"
eng_min = 0
eng_max = 65535
)";
  return t.str();
}

class GatewayHil : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_gateway_hil_" + std::to_string(getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
    plan_ = (dir_ / "prbsUnc.plan").string();
    const std::string design =
        std::string(EXCITE_TOOL) + " design -q --plant alatiqi4x4 --preset prbsUnc -o " + plan_;
    ASSERT_EQ(std::system(design.c_str()), 0) << design;
    server_ = std::make_unique<FaultServer>();
    for (int i = 0; i < 4; ++i) put_float(*server_, true, 100 + 2 * i, static_cast<float>(kU0[i]));
    for (int j = 0; j < 4; ++j) put_float(*server_, false, 200 + 2 * j, static_cast<float>(kY0));
    peer_ = std::thread([this] {
      while (!stop_peer_) {
        server_->set_input(300, server_->holding(108));  // the PLC echoes the heartbeat
        std::this_thread::sleep_for(200us);
      }
    });
    write_config(config_text(server_->port()));
    log_ = (dir_ / "run.csv").string();
  }

  void TearDown() override {
    stop_peer_ = true;
    if (peer_.joinable()) peer_.join();
    server_.reset();
    fs::remove_all(dir_);
  }

  void write_config(const std::string& text) {
    config_ = (dir_ / "gateway.toml").string();
    std::ofstream(config_) << text;
  }

  std::unique_ptr<GatewayProcess> start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"--config", config_, "--plan", plan_, "--log", log_};
    args.insert(args.end(), extra.begin(), extra.end());
    return std::make_unique<GatewayProcess>(EXCITE_GATEWAY, args, (dir_ / "gw").string());
  }

  runlog::RunLog read_log() {
    runlog::ReadResult r = runlog::read_run_log(log_);
    EXPECT_TRUE(r.ok()) << (r.error ? r.error->to_string() : "");
    return r.log;
  }

  // Waits until the gateway has written at least n FC16 requests.
  bool wait_for_writes(int n, std::chrono::milliseconds timeout = 10s) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (server_->count(16) < n) {
      if (std::chrono::steady_clock::now() > until) return false;
      std::this_thread::sleep_for(5ms);
    }
    return true;
  }

  void expect_baseline_held() {
    for (int i = 0; i < 4; ++i) {
      EXPECT_EQ(holding_float(*server_, 100 + 2 * i), static_cast<float>(kU0[i])) << i;
    }
  }

  fs::path dir_;
  std::string plan_;
  std::string config_;
  std::string log_;
  std::unique_ptr<FaultServer> server_;
  std::thread peer_;
  std::atomic<bool> stop_peer_{false};
};

std::size_t count_flag(const runlog::RunLog& log, std::uint32_t flag) {
  std::size_t n = 0;
  for (auto f : log.flags) n += (f & flag) != 0 ? 1 : 0;
  return n;
}

TEST_F(GatewayHil, StreamsTheCaseStudyPlanToCompletionAndExitsZero) {
  auto gw = start({"--start"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog log = read_log();
  EXPECT_GT(log.rows(), 4080U);
  EXPECT_EQ(log.input_names, (std::vector<std::string>{"L", "V", "S", "F"}));
  EXPECT_EQ(log.output_names, (std::vector<std::string>{"xD", "xS", "xB", "T"}));
  double peak = 0.0;
  for (const auto& du : log.du) {
    for (double v : du) peak = std::max(peak, std::abs(v));
    EXPECT_EQ(du.back(), 0.0);
  }
  EXPECT_NEAR(peak, 1.0, 1e-12);  // the prbsUnc amplitude
  expect_baseline_held();
  EXPECT_GE(server_->count(16), 4080);
  EXPECT_NE(gw->err().find("ring overruns 0"), std::string::npos) << gw->err();
  const std::string err = gw->err();
  const auto at = err.find("rows logged ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_EQ(std::stoul(err.substr(at + 12)), log.rows());
  // The resident-memory lines, for the README's figures.
  std::istringstream lines(err);
  for (std::string line; std::getline(lines, line);) {
    if (line.find("memory") != std::string::npos) std::printf("%s\n", line.c_str());
  }
  EXPECT_NE(err.find("memory after start-up: VmRSS"), std::string::npos);
}

TEST_F(GatewayHil, SigtermRampsOutFlushesAValidLogAndExitsSix) {
  auto gw = start();
  ASSERT_TRUE(wait_for_writes(5));
  gw->send_line("start");
  std::this_thread::sleep_for(400ms);
  gw->signal(SIGTERM);
  const auto rc = gw->wait(20s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 6) << gw->err();
  const runlog::RunLog log = read_log();
  EXPECT_GT(log.rows(), 20U);
  for (const auto& du : log.du) EXPECT_EQ(du.back(), 0.0);
  expect_baseline_held();
  EXPECT_NE(gw->err().find("aborted by operator"), std::string::npos) << gw->err();
}

TEST_F(GatewayHil, KilledRunLeavesAValidLogUpToItsLastTick) {
  auto gw = start({"--start"});
  ASSERT_TRUE(wait_for_writes(200));
  gw->signal(SIGKILL);  // no flush, no ramp-out: the log must still be valid
  ASSERT_EQ(gw->wait(10s).value_or(-1), 128 + SIGKILL);
  const runlog::RunLog log = read_log();
  EXPECT_GE(log.rows(), 150U);
  EXPECT_EQ(log.k.back(), log.rows() - 1);
}

TEST_F(GatewayHil, TestLimitExcursionSuspendsThenResumesWithHysteresisAndDwell) {
  auto gw = start({"--start"});
  ASSERT_TRUE(wait_for_writes(100));
  put_float(*server_, false, 200, static_cast<float>(kY0 + 6.0));  // beyond test_high
  std::this_thread::sleep_for(200ms);
  put_float(*server_, false, 200, static_cast<float>(kY0 + 4.8));  // inside, not the band
  std::this_thread::sleep_for(200ms);
  put_float(*server_, false, 200, static_cast<float>(kY0));
  std::this_thread::sleep_for(300ms);
  gw->signal(SIGTERM);
  ASSERT_EQ(gw->wait(20s).value_or(-1), 6) << gw->err();
  const runlog::RunLog log = read_log();
  // Suspended from the excursion through the no-band period and the dwell: ≥ 400 ms.
  std::size_t first = log.rows();
  std::size_t last = 0;
  for (std::size_t r = 0; r < log.rows(); ++r) {
    if ((log.flags[r] & runlog::kSuspended) != 0) {
      first = std::min(first, r);
      last = r;
    }
  }
  ASSERT_LT(first, last);
  EXPECT_GE(last - first, 150U);  // ≥ 0.4 s at 2 ms, allowing skipped ticks on a busy host
  // After the dwell the excitation resumed: nonzero du after the suspension.
  bool resumed = false;
  for (std::size_t r = last + 1; r < log.rows(); ++r) resumed = resumed || log.du[0][r] != 0.0;
  EXPECT_TRUE(resumed);
  EXPECT_NE(gw->err().find("running -> suspended"), std::string::npos) << gw->err();
  EXPECT_NE(gw->err().find("suspended -> running"), std::string::npos) << gw->err();
}

TEST_F(GatewayHil, CommLossHoldsReconnectsAndMarksTheLog) {
  auto gw = start({"--start"});
  ASSERT_TRUE(wait_for_writes(100));
  server_->inject(FaultServer::Fault::drop, 6);  // the peer resets the connection 6 times
  std::this_thread::sleep_for(500ms);
  gw->signal(SIGTERM);
  ASSERT_EQ(gw->wait(20s).value_or(-1), 6) << gw->err();
  const runlog::RunLog log = read_log();
  EXPECT_GE(count_flag(log, runlog::kCommLost), 6U);
  EXPECT_NE(gw->err().find("communication lost"), std::string::npos) << gw->err();
  EXPECT_NE(gw->err().find("communication restored"), std::string::npos) << gw->err();
  expect_baseline_held();  // reconnected: the ramp-out reached the peer
}

TEST_F(GatewayHil, OperatorStartsBySignalAndAbortsByTheCommandRegister) {
  auto gw = start();
  ASSERT_TRUE(wait_for_writes(20));
  EXPECT_EQ(holding_float(*server_, 100), static_cast<float>(kU0[0]));  // armed: baseline
  gw->signal(SIGUSR1);                                                  // start
  std::this_thread::sleep_for(300ms);
  server_->set_input(301, 4);  // abort
  const auto rc = gw->wait(20s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 6) << gw->err();
  const runlog::RunLog log = read_log();
  bool excited = false;
  for (double v : log.du[0]) excited = excited || v != 0.0;
  EXPECT_TRUE(excited);
  expect_baseline_held();
}

TEST_F(GatewayHil, OperatorSuspendAndResumeOnStdin) {
  auto gw = start({"--start"});
  ASSERT_TRUE(wait_for_writes(50));
  gw->send_line("suspend");
  std::this_thread::sleep_for(200ms);
  gw->send_line("resume");
  std::this_thread::sleep_for(200ms);
  gw->send_line("abort");
  ASSERT_EQ(gw->wait(20s).value_or(-1), 6) << gw->err();
  EXPECT_GT(count_flag(read_log(), runlog::kSuspended), 20U);
  EXPECT_NE(gw->err().find("suspended -> running"), std::string::npos) << gw->err();
}

TEST_F(GatewayHil, DryRunTouchesNothingAndPrintsTheWrites) {
  GatewayProcess gw(EXCITE_GATEWAY, {"--config", config_, "--plan", plan_, "--dry-run"},
                    (dir_ / "dry").string());
  ASSERT_EQ(gw.wait(20s).value_or(-1), 0) << gw.err();
  EXPECT_NE(gw.out().find("would write every tick"), std::string::npos) << gw.out();
  EXPECT_NE(gw.out().find("register   100 float32 CDAB"), std::string::npos) << gw.out();
  EXPECT_TRUE(server_->seen().empty());
  EXPECT_FALSE(fs::exists(log_));
}

// ---- Bad input: refused before anything is written to the field ----

TEST_F(GatewayHil, PlanForAnotherConfigurationIsRefused) {
  write_config(config_text(server_->port(), 3));
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 3);
  EXPECT_NE(gw->err().find("plan channels = 4, expected 3"), std::string::npos) << gw->err();
  EXPECT_EQ(server_->count(16), 0);
}

TEST_F(GatewayHil, BaselineOutsideTheLimitsRefusesToArm) {
  put_float(*server_, true, 102, 75.0F);  // V baseline 75, limits [50, 70]
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 5);
  EXPECT_NE(gw->err().find("refused to arm: input[1] baseline = 75"), std::string::npos)
      << gw->err();
  EXPECT_EQ(server_->count(16), 0);
}

TEST_F(GatewayHil, UnreachableDeviceIsRefused) {
  const std::uint16_t port = server_->port();
  stop_peer_ = true;
  peer_.join();
  server_->stop();
  write_config(config_text(port));
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 4);
  EXPECT_NE(gw->err().find("expected a reachable Modbus peer"), std::string::npos) << gw->err();
}

TEST_F(GatewayHil, OverlappingRegisterMapIsRefused) {
  write_config(config_text(server_->port(), 4, "101"));
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 2);
  EXPECT_NE(gw->err().find("expected no overlap"), std::string::npos) << gw->err();
  EXPECT_TRUE(server_->seen().empty());
}

TEST_F(GatewayHil, RegisterBeyondTheProtocolIsRefused) {
  write_config(config_text(server_->port(), 4, "65535"));
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 2);
  EXPECT_NE(gw->err().find("setpoints[1].address = 65535"), std::string::npos) << gw->err();
  EXPECT_TRUE(server_->seen().empty());
}

TEST_F(GatewayHil, UnknownWordOrderIsRefused) {
  write_config(config_text(server_->port(), 4, "", "BACD"));
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 2);
  EXPECT_NE(gw->err().find("word_order = \"BACD\""), std::string::npos) << gw->err();
  EXPECT_TRUE(server_->seen().empty());
}

TEST_F(GatewayHil, CorruptPlanIsRefused) {
  {
    std::fstream f(plan_, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(30);
    f.put('\x55');
  }
  auto gw = start({"--start"});
  ASSERT_EQ(gw->wait(20s).value_or(-1), 3);
  EXPECT_NE(gw->err().find("stored CRC-32"), std::string::npos) << gw->err();
  EXPECT_TRUE(server_->seen().empty());
}

}  // namespace
}  // namespace excite::test
