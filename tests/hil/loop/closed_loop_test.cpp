// SPDX-License-Identifier: MIT
// The gateway in closed loop (issue 42 §2), the real processes: excite-gateway writes test
// offsets to excite-plant --controller (woodberry2x2 under the BLT-tuned PI of
// sim/control/examples) through the pair `excite loop-config --controller` writes. Asserted
// on the plant's side (its registers read with libmodbus, its controller log): a run ends
// with every offset at zero and the controller in control; the controller switched to
// manual mid-test suspends and then aborts the test, the offsets back at zero; a SIGKILLed
// gateway leaves the plant's watchdog to zero them.
#include <modbus.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"
#include "recording_proxy.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;
using SteadyClock = std::chrono::steady_clock;

// sim/server's closed-loop default map for woodberry2x2 (n = m = 2).
constexpr int kOffsets = 500;  // holding: u1, u2 offsets, then y1, y2 setpoint offsets
constexpr int kMode = 514;     // input: the controller's mode
constexpr int kSwitch = 410;   // holding: the operator's switch

class Plc {  // a libmodbus client of the plant: an operator's HMI beside the gateway
 public:
  explicit Plc(std::uint16_t port) : ctx_(modbus_new_tcp("127.0.0.1", port)) {
    if (ctx_ != nullptr && modbus_connect(ctx_) != 0) {
      modbus_free(ctx_);
      ctx_ = nullptr;
    }
  }
  ~Plc() {
    if (ctx_ != nullptr) {
      modbus_close(ctx_);
      modbus_free(ctx_);
    }
  }
  Plc(const Plc&) = delete;
  Plc& operator=(const Plc&) = delete;
  bool ok() const { return ctx_ != nullptr; }
  // The four offset registers as floats (ABCD); empty when the read failed.
  std::vector<float> offsets() {
    std::uint16_t r[8];
    if (modbus_read_registers(ctx_, kOffsets, 8, r) != 8) return {};
    std::vector<float> out;
    for (int k = 0; k < 4; ++k) {
      const std::uint32_t bits = (std::uint32_t{r[2 * k]} << 16) | r[2 * k + 1];
      float x;
      std::memcpy(&x, &bits, sizeof x);
      out.push_back(x);
    }
    return out;
  }
  int mode() {
    std::uint16_t v = 0;
    return modbus_read_input_registers(ctx_, kMode, 1, &v) == 1 ? v : -1;
  }
  int holding(int address) {
    std::uint16_t v = 0;
    return modbus_read_registers(ctx_, address, 1, &v) == 1 ? v : -1;
  }
  bool set_switch(int value) {
    return modbus_write_register(ctx_, kSwitch, static_cast<std::uint16_t>(value)) == 1;
  }

 private:
  modbus_t* ctx_;
};

class ClosedLoopGateway : public LoopTest {
 protected:
  // The pair for woodberry2x2 under the PI, the gateway ticking every 2 ms, the plant in
  // lock-step with its controller log.
  std::uint16_t start(const std::string& extra_config, std::vector<std::string> plant_args) {
    plant_args.insert(plant_args.end(),
                      {"--clock", "lockstep", "--controller-log", path("controller.csv").string()});
    const std::string args = "--controller " + kPi + " --period-s 0.002 " + extra_config;
    const std::uint16_t port = start_loop("woodberry2x2", args, plant_args);
    plan_ = design("woodberry2x2", "prbsUnc");
    return port;
  }
  std::vector<std::vector<std::string>> controller_log() const {
    std::ifstream in(path("controller.csv"));
    std::vector<std::vector<std::string>> rows;
    std::string line;
    std::getline(in, line);  // header
    while (std::getline(in, line)) {
      std::vector<std::string> cells;
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
      rows.push_back(cells);
    }
    return rows;
  }
  // Waits until the plant's controller reads mode `mode` (2: test, offsets in force).
  bool wait_for_mode(Plc& plc, int mode) {
    const auto until = SteadyClock::now() + 20s;
    while (plc.mode() != mode && SteadyClock::now() < until) std::this_thread::sleep_for(5ms);
    return plc.mode() == mode;
  }
  static bool all_zero(const std::vector<float>& xs) {
    if (xs.empty()) return false;
    for (const float x : xs)
      if (x != 0.0F) return false;
    return true;
  }

  fs::path plan_;
};

// GIVEN setpoint offsets streamed to the running PI, THEN the run completes, the offsets are
// at zero on the plant's side and the controller is in control; every setpoint the plant's
// controller had in force is the offset the gateway logged, row for row.
TEST_F(ClosedLoopGateway, ARunEndsWithEveryOffsetAtZeroAndTheControllerInControl) {
  const std::uint16_t port = start("--offsets setpoint --output-range 0.5", {"--watchdog-s", "2"});
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  ASSERT_EQ(gw->wait(60s).value_or(-1), 0) << gw->err();
  EXPECT_NE(gw->err().find("safe after"), std::string::npos) << gw->err();
  EXPECT_NE(gw->err().find("closed loop: the controller left its mode 0 times, MVs clamped or "
                           "wound up 0 times"),
            std::string::npos)
      << gw->err();
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  EXPECT_TRUE(all_zero(plc.offsets())) << "the offsets at zero on the plant's side";
  EXPECT_EQ(plc.mode(), 1) << "the controller in control";

  const runlog::RunLog gateway = read_log_or_fail(path("gw.csv"));
  ASSERT_EQ(gateway.closed_loop.r.size(), 2U) << "run-log v4: r_y1, r_y2";
  const auto rows = controller_log();
  ASSERT_EQ(rows.size(), gateway.rows()) << "one plant sample per gateway tick";
  double largest = 0.0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 14U);
    for (std::size_t j = 0; j < 2; ++j) {
      const double logged = gateway.closed_loop.r[j][k];  // r_<CV>: the offset written
      ASSERT_EQ(std::stod(rows[k][12 + j]), static_cast<double>(static_cast<float>(logged)))
          << "row " << k << ": the plant's setpoint in force is the gateway's offset";
      largest = std::max(largest, std::abs(logged));
    }
  }
  EXPECT_GT(largest, 0.01) << "the setpoints were excited";
  EXPECT_EQ(rows.back()[3], "control");
  EXPECT_EQ(rows.back()[12], "0");
  EXPECT_EQ(rows.back()[13], "0");
  stop_plant_and_read_its_log();
}

// Run-log v4 from the gateway (issue 42 §2): GIVEN an MV dither streamed to the running PI,
// THEN the gateway's own log says closed loop, mv, the controller from its configuration, and
// row by row its r (the offsets written), uc (the controller's moves), du (what the plant
// got), st and mode equal the plant's own controller log; u = the MV's operating point + du;
// and `excite identify` reads the log with nothing passed by hand.
TEST_F(ClosedLoopGateway, TheGatewaysOwnLogIsRunLogV4EqualToThePlantsControllerLog) {
  start("--offsets mv --output-range 5", {"--watchdog-s", "2"});
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  ASSERT_EQ(gw->wait(60s).value_or(-1), 0) << gw->err();
  std::ifstream text_in(path("gw.csv"));
  const std::string text((std::istreambuf_iterator<char>(text_in)),
                         std::istreambuf_iterator<char>());
  EXPECT_EQ(text.substr(0, text.find('\n')), "# excite run log v4");
  EXPECT_NE(text.find("\n# loop: closed\n# excitation: mv\n# controller: pi "
                      "woodberry2x2.pi.toml\n"),
            std::string::npos)
      << text.substr(0, 600);
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_EQ(log.format_version, 4);
  const runlog::ClosedLoopLog& cl = log.closed_loop;
  ASSERT_TRUE(cl.closed);
  EXPECT_EQ(cl.excitation, runlog::Excitation::mv);
  EXPECT_EQ(cl.r_channels, (std::vector<std::size_t>{0, 1}));
  ASSERT_EQ(log.input_names.size(), 2U);
  EXPECT_EQ(log.input_names[0], "u1") << "the log's inputs are the MVs, not the offsets";

  // The plant's controller log: event,k,t_min,mode,o_u1,o_u2,uc_u1,uc_u2,du_u1,du_u2,
  // st_u1,st_u2,ysp_y1,ysp_y2 (float32 registers: compare as float).
  const auto rows = controller_log();
  ASSERT_EQ(rows.size(), log.rows()) << "one plant sample per gateway tick";
  const auto same = [](const std::string& cell, double logged) {
    return static_cast<float>(std::stod(cell)) == static_cast<float>(logged);
  };
  double largest_r = 0.0;
  double largest_gap = 0.0;  // |du − (uc + r)|: > 0 only where an MV was clamped
  for (std::size_t k = 0; k < rows.size(); ++k) {
    ASSERT_EQ(rows[k].size(), 14U);
    for (std::size_t i = 0; i < 2; ++i) {
      ASSERT_TRUE(same(rows[k][4 + i], cl.r[i][k])) << "row " << k << " r_" << i;
      ASSERT_TRUE(same(rows[k][6 + i], cl.uc[i][k])) << "row " << k << " uc_" << i;
      ASSERT_TRUE(same(rows[k][8 + i], log.du[i][k])) << "row " << k << " du_" << i;
      ASSERT_EQ(std::stoi(rows[k][10 + i]), static_cast<int>(cl.st[i][k])) << "row " << k;
      ASSERT_EQ(log.u[i][k] - log.du[i][k], log.u[i][0] - log.du[i][0]) << "u = u0 + du";
      largest_r = std::max(largest_r, std::abs(cl.r[i][k]));
      largest_gap = std::max(largest_gap, std::abs(log.du[i][k] - cl.uc[i][k] - cl.r[i][k]));
    }
    ASSERT_EQ(rows[k][3], std::string(runlog::to_text(cl.mode[k]))) << "row " << k;
  }
  EXPECT_GT(largest_r, 0.01) << "the MVs were dithered";
  // u = mv_baseline + du: loop-config wrote woodberry2x2's operating point (zeros, a linear
  // plant) as mv_baseline; the constancy of u − du above holds for any.
  std::ifstream toml_in(path("gateway.toml"));
  const std::string toml((std::istreambuf_iterator<char>(toml_in)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(toml.find("\nmv_baseline = [0.0, 0.0]\n"), std::string::npos) << toml;
  EXPECT_EQ(log.u[0][0] - log.du[0][0], 0.0);
  std::printf("[ measured ] %zu rows equal; largest |du - uc - r| %.3g\n", rows.size(),
              largest_gap);

  const std::string identify = std::string(EXCITE_TOOL) + " identify " + path("gw.csv").string() +
                               " -o " + path("model.json").string() + " > " +
                               path("identify.out").string() + " 2>&1";
  EXPECT_TRUE(shell(identify)) << [&] {
    std::ifstream o(path("identify.out"));
    return std::string((std::istreambuf_iterator<char>(o)), std::istreambuf_iterator<char>());
  }();
  EXPECT_TRUE(fs::exists(path("model.json")));
  stop_plant_and_read_its_log();
}

// GIVEN a test in progress, WHEN the operator switches the controller to manual, THEN the
// gateway suspends (the offsets ramp to zero), aborts after controller_timeout_s, and is safe
// once the controller is back in control: exit 6, the summary counts the episode.
TEST_F(ClosedLoopGateway, ManualMidTestSuspendsThenAbortsWithTheOffsetsAtZero) {
  const std::uint16_t port = start(
      "--offsets setpoint --output-range 0.5 --controller-timeout-s 0.3", {"--watchdog-s", "2"});
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  auto gw = start_gateway(plan_, {"--start"});  // real time: 2 ms ticks, 1.9 s of plan
  ASSERT_TRUE(wait_for_mode(plc, 2)) << "the test is running: " << gw->err();
  std::this_thread::sleep_for(50ms);
  ASSERT_TRUE(plc.set_switch(0)) << modbus_strerror(errno);
  const auto until = SteadyClock::now() + 20s;
  while (gw->err().find("-> aborted") == std::string::npos && SteadyClock::now() < until) {
    std::this_thread::sleep_for(10ms);
  }
  const std::string during = gw->err();
  EXPECT_NE(during.find("-> suspended"), std::string::npos) << during;
  ASSERT_NE(during.find("-> aborted"), std::string::npos) << during;
  EXPECT_LT(during.find("-> suspended"), during.find("-> aborted")) << "suspend, then abort";
  std::this_thread::sleep_for(100ms);
  EXPECT_TRUE(all_zero(plc.offsets())) << "aborted: the offsets back at zero on the plant";
  EXPECT_FALSE(gw->wait(0ms).has_value()) << "not safe while the controller is in manual";
  ASSERT_TRUE(plc.set_switch(1));  // the operator puts the controller back in control
  ASSERT_EQ(gw->wait(30s).value_or(-1), 6) << gw->err();  // aborted, baseline confirmed
  const std::string err = gw->err();
  EXPECT_NE(err.find("safe after"), std::string::npos) << err;
  EXPECT_NE(err.find("aborted: the controller left its mode or an MV was limited too long"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("the controller left its mode 1 times"), std::string::npos) << err;
  EXPECT_TRUE(all_zero(plc.offsets()));
  EXPECT_EQ(plc.mode(), 1);
  stop_plant_and_read_its_log();
}

// GIVEN a test in progress, WHEN the gateway is SIGKILLed, THEN the plant's watchdog returns
// every offset to zero and keeps the controller in control (its registers, its log).
TEST_F(ClosedLoopGateway, AKilledGatewayLeavesThePlantsWatchdogToZeroTheOffsets) {
  // No test limits: an MV dither moves xD by up to 0.9 (a 0.5 limit would suspend the test,
  // and a suspended test has its offsets at zero already).
  const std::uint16_t port = start("--offsets mv --output-range 5 --watchdog-s 0.5", {});
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  auto gw = start_gateway(plan_, {"--start"});  // real time: 2 ms ticks, 1.9 s of plan
  ASSERT_TRUE(wait_for_mode(plc, 2)) << gw->err();
  std::this_thread::sleep_for(200ms);
  ASSERT_FALSE(gw->wait(0ms).has_value()) << "the run ended too soon: " << gw->err();
  EXPECT_FALSE(all_zero(plc.offsets())) << "the MV offsets are in force: " << gw->err();
  gw->signal(SIGKILL);
  const auto killed = SteadyClock::now();
  ASSERT_EQ(gw->wait(10s).value_or(-1), 128 + SIGKILL);
  while (SteadyClock::now() - killed < 1500ms && plc.holding(kWatchdogTrips) != 1) {
    std::this_thread::sleep_for(10ms);
  }
  const double after_s = std::chrono::duration<double>(SteadyClock::now() - killed).count();
  EXPECT_EQ(plc.holding(kWatchdogTrips), 1);
  EXPECT_GE(after_s, 0.45) << "not before the watchdog's 0.5 s";
  EXPECT_TRUE(all_zero(plc.offsets())) << "every offset back at zero";
  EXPECT_EQ(plc.mode(), 1) << "the controller kept in control";
  const auto rows = controller_log();
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows.back()[0], "watchdog") << "the plant's own log records it";
  EXPECT_EQ(rows.back()[3], "control");
  EXPECT_EQ(rows.back()[4], "0");
  EXPECT_EQ(rows.back()[5], "0");
  EXPECT_NE(plant_->stderr_text().find("every test offset returned to zero"), std::string::npos);
  std::printf("[ measured ] offsets at zero %.3f s after SIGKILL (watchdog 0.5 s)\n", after_s);
  stop_plant_and_read_its_log();
}

// GIVEN MV offsets larger than the controller's MV limits (a PI with limits ±0.05 against a
// dither of up to 0.14), THEN every MV the plant reports wound up or clamped suspends the
// test at the next tick (the offset written there is zero), the run still completes, and the
// summary counts the episodes.
TEST_F(ClosedLoopGateway, AClampedOrWoundUpMvSuspendsTheTestAtTheNextTick) {
  std::ifstream in(kPi);
  std::string pi((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (std::size_t at = pi.find("0.3"); at != std::string::npos; at = pi.find("0.3", at + 1)) {
    pi.replace(at, 3, "0.05");  // min = -0.3, max = 0.3 → ±0.05
  }
  const fs::path tight = path("tight.pi.toml");
  std::ofstream(tight) << pi;
  const std::string args = "--controller " + tight.string() +
                           " --period-s 0.002 --offsets mv --output-range 5 --watchdog-s 2";
  start_loop("woodberry2x2", args,
             {"--clock", "lockstep", "--controller-log", path("controller.csv").string()});
  plan_ = design("woodberry2x2", "prbsUnc");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  ASSERT_EQ(gw->wait(120s).value_or(-1), 0) << gw->err();
  const std::string err = gw->err();
  const auto at = err.find("MVs clamped or wound up ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_GT(std::stoul(err.substr(at + 24)), 10U) << err;
  const auto rows = controller_log();
  std::size_t limited = 0;
  for (std::size_t k = 0; k + 1 < rows.size(); ++k) {
    for (std::size_t i = 0; i < 2; ++i) {
      const int st = std::stoi(rows[k][10 + i]);
      if (st == 1 || st == 2 || st == 3) {
        ++limited;
        EXPECT_EQ(rows[k + 1][4], "0") << "sample " << k + 1 << ": suspended, offsets zero";
        EXPECT_EQ(rows[k + 1][5], "0") << "sample " << k + 1;
      }
    }
  }
  EXPECT_GT(limited, 10U) << "the limits were reached";
  stop_plant_and_read_its_log();
}

// SIGTERM mid-test (the operator's stop): aborted, every offset back at zero, read back and
// held with the controller in control: safe, exit 6.
TEST_F(ClosedLoopGateway, SigtermEndsSafeWithTheOffsetsAtZero) {
  const std::uint16_t port = start("--offsets both --output-range 5", {"--watchdog-s", "2"});
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  // --offsets both: four channels (u1, u2 offsets, then y1, y2 setpoint offsets).
  const fs::path plan4 = path("four.plan");
  ASSERT_TRUE(shell(std::string(EXCITE_TOOL) +
                    " design -q --plant alatiqi4x4 --preset prbsUnc -o " + plan4.string() + " > " +
                    path("design4.out").string()));
  auto gw = start_gateway(plan4, {"--start"});  // real time, 2 ms ticks
  ASSERT_TRUE(wait_for_mode(plc, 2)) << gw->err();
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(all_zero(plc.offsets()));
  gw->signal(SIGTERM);
  ASSERT_EQ(gw->wait(30s).value_or(-1), 6) << gw->err();
  EXPECT_NE(gw->err().find("safe after"), std::string::npos) << gw->err();
  EXPECT_TRUE(all_zero(plc.offsets()));
  EXPECT_EQ(plc.mode(), 1);
  stop_plant_and_read_its_log();
}

// The plant's own controller log at its last sample row: every offset (o_u1, o_u2) and every
// setpoint in force (ysp_y1, ysp_y2) at zero, the controller in control.
void expect_last_sample_safe(const std::vector<std::vector<std::string>>& rows) {
  auto last = rows.rbegin();
  while (last != rows.rend() && (*last)[0] != "sample") ++last;
  ASSERT_NE(last, rows.rend()) << "the plant logged samples";
  EXPECT_EQ((*last)[3], "control");
  for (const std::size_t c : {4U, 5U, 12U, 13U}) EXPECT_EQ((*last)[c], "0") << "column " << c;
}

// §2 "a full disk ends that way": GIVEN the gateway under `ulimit -f 20` (prlimit), its run
// log (v4) growing past the limit mid-run, THEN the write fails (EFBIG, not SIGXFSZ), the
// test stops and returns: exit 13, every offset at zero on the plant's side and the
// controller in control (its registers and its own log).
TEST_F(ClosedLoopGateway, AFileSizeLimitOnTheLogEndsWithTheOffsetsAtZeroInControl) {
  if (access(kPrlimit, X_OK) != 0) GTEST_SKIP() << kPrlimit << " not found (util-linux)";
  const std::uint16_t port = start("--offsets setpoint --output-range 0.5", {"--watchdog-s", "2"});
  GatewayProcess gw(kPrlimit,
                    {"--fsize=" + std::to_string(kSizeLimit), EXCITE_GATEWAY, "--config",
                     path("gateway.toml").string(), "--plan", plan_.string(), "--log",
                     path("gw.csv").string(), "--start", "--clock", "lockstep"},
                    path("gw").string());
  ASSERT_EQ(gw.wait(60s).value_or(-1), 13) << gw.err();
  EXPECT_NE(gw.err().find("File too large (EFBIG)"), std::string::npos) << gw.err();
  EXPECT_NE(gw.err().find("safe after"), std::string::npos) << gw.err();
  EXPECT_LE(static_cast<long>(fs::file_size(path("gw.csv"))), kSizeLimit);
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  EXPECT_TRUE(all_zero(plc.offsets())) << "the offsets at zero on the plant's side";
  EXPECT_EQ(plc.mode(), 1) << "the controller in control";
  stop_plant_and_read_its_log();
  expect_last_sample_safe(controller_log());
}

// §3 faults: GIVEN setpoint offsets in force, WHEN the plant is frozen 10 s (SIGSTOP, then
// SIGCONT), THEN the gateway loses the link (comm loss), finds the plant again, and the run
// ends with every offset at zero on the plant's side and the controller in control (its
// registers and its own log).
TEST_F(ClosedLoopGateway, APlantFrozenTenSecondsEndsWithTheOffsetsAtZeroInControl) {
  const std::uint16_t port = start("--offsets setpoint --output-range 5", {"--watchdog-s", "2"});
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  auto gw = start_gateway(plan_, {"--start"});  // real time: 2 ms ticks, 1.9 s of plan
  ASSERT_TRUE(wait_for_mode(plc, 2)) << gw->err();
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(all_zero(plc.offsets())) << "the setpoint offsets are in force";
  plant_->signal(SIGSTOP);
  std::this_thread::sleep_for(10s);
  plant_->signal(SIGCONT);
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_TRUE(*rc == 0 || *rc == 6) << "completed or aborted, safe either way: " << err;
  EXPECT_NE(err.find("communication lost"), std::string::npos) << err;
  EXPECT_NE(err.find("safe after"), std::string::npos) << err;
  EXPECT_TRUE(all_zero(plc.offsets())) << "the offsets at zero on the plant's side";
  EXPECT_EQ(plc.mode(), 1) << "the controller in control";
  expect_last_sample_safe(controller_log());
  std::printf("[ measured ] frozen 10 s: gateway exit %d\n", *rc);
  stop_plant_and_read_its_log();
}

// §3 faults: GIVEN MV offsets in force through a TCP relay, WHEN the link is cut for 2 s (the
// relay drops every connection and refuses new ones), THEN the plant's watchdog (0.5 s)
// zeroes every offset while the link is down, the controller stays in control, and once the
// link is back the gateway finds the plant again and ends with the offsets at zero.
TEST_F(ClosedLoopGateway, ALinkCutEndsWithTheOffsetsAtZeroInControl) {
  const std::string args = "--offsets mv --output-range 5 --watchdog-s 0.5";
  const std::uint16_t port = start(args, {});
  RecordingProxy relay(port);
  loop_config("woodberry2x2", relay.port(),
              "--controller " + kPi + " --period-s 0.002 " + args);  // the gateway → the relay
  Plc plc(port);                                                     // the operator, direct
  ASSERT_TRUE(plc.ok());
  auto gw = start_gateway(plan_, {"--start"});
  ASSERT_TRUE(wait_for_mode(plc, 2)) << gw->err();
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(all_zero(plc.offsets())) << "the MV offsets are in force";
  relay.set_cut(true);
  std::this_thread::sleep_for(1500ms);
  EXPECT_TRUE(all_zero(plc.offsets())) << "link down: the plant's watchdog zeroed the offsets";
  EXPECT_EQ(plc.mode(), 1) << "link down: the controller kept in control";
  EXPECT_EQ(plc.holding(kWatchdogTrips), 1);
  std::this_thread::sleep_for(500ms);
  relay.set_cut(false);
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_TRUE(*rc == 0 || *rc == 6) << "completed or aborted, safe either way: " << err;
  EXPECT_NE(err.find("communication lost"), std::string::npos) << err;
  EXPECT_NE(err.find("safe after"), std::string::npos) << err;
  EXPECT_TRUE(all_zero(plc.offsets()));
  EXPECT_EQ(plc.mode(), 1);
  const auto rows = controller_log();
  EXPECT_TRUE(std::any_of(rows.begin(), rows.end(), [](const auto& row) {
    return row[0] == "watchdog";
  })) << "the plant's own log records the trip";
  expect_last_sample_safe(rows);
  std::printf("[ measured ] link cut 2 s: gateway exit %d\n", *rc);
  stop_plant_and_read_its_log();
}

// §3: a third-party Modbus server (pymodbus, tests/hil/loop/pymodbus_dcs.py) standing in for
// a DCS that adds the test offset to its own (fixed) controller output: the gateway streams
// to it with the gateway.toml of `excite loop-config --controller` as to excite-plant, the
// offsets the DCS held at each heartbeat are the r the gateway logged, the log's uc is the
// DCS's controller output, and the run ends with the offsets at zero and the DCS in control.
TEST_F(ClosedLoopGateway, TheGatewayStreamsToAPymodbusDcsAndEndsWithTheOffsetsAtZero) {
  if (!shell("/usr/bin/python3 -c 'import pymodbus' 2>/dev/null")) {
    GTEST_SKIP() << "python3-pymodbus is not installed";
  }
  PlantRunner dcs("/usr/bin/python3",
                  {std::string(EXCITE_LOOP_DIR) + "/pymodbus_dcs.py", "--record",
                   path("dcs.csv").string(), "--uc", "0.1", "-0.05", "--watchdog-s", "1"},
                  path("dcs.stderr"));
  const auto port = dcs.wait_listening(10s);
  ASSERT_TRUE(port.has_value()) << dcs.stderr_text();
  // A DCS is no simulator: real time, 5 ms ticks (prbsUnc: 950 rows, about 5 s).
  loop_config("woodberry2x2", *port, "--controller " + kPi + " --offsets mv --period-s 0.005");
  plan_ = design("woodberry2x2", "prbsUnc");
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value());
  ASSERT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("safe after"), std::string::npos) << gw->err();
  ASSERT_EQ(dcs.stop(SIGTERM, 10s).value_or(-1), 0) << dcs.stderr_text();

  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_TRUE(log.closed_loop.closed);
  const runlog::ClosedLoopLog& cl = log.closed_loop;
  std::ifstream rec(path("dcs.csv"));
  std::size_t seen = 0;
  std::size_t matched = 0;
  double largest = 0.0;
  std::vector<std::string> final_row;
  for (std::string line; std::getline(rec, line);) {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (cells.empty()) continue;
    if (cells[0] == "final") {
      final_row = cells;
      continue;
    }
    const unsigned long heartbeat = std::stoul(cells[0]);
    if (heartbeat == 0 || heartbeat - 1 >= log.rows()) continue;  // before the first write
    ++seen;
    const std::size_t k = heartbeat - 1;  // tick k wrote heartbeat k + 1 with its offsets
    bool same = true;
    for (std::size_t i = 0; i < 2; ++i) {
      same = same && static_cast<float>(std::stod(cells[1 + i])) == static_cast<float>(cl.r[i][k]);
      largest = std::max(largest, std::abs(std::stod(cells[1 + i])));
    }
    matched += same ? 1 : 0;
  }
  EXPECT_GT(seen, log.rows() / 2) << "the DCS saw too few heartbeats";
  EXPECT_EQ(matched, seen) << "the offsets at the DCS differ from the gateway's r";
  EXPECT_GT(largest, 0.01) << "the DCS's MVs were dithered";
  ASSERT_EQ(final_row.size(), 6U) << "the DCS's last state";
  for (std::size_t c = 1; c <= 4; ++c) EXPECT_EQ(std::stod(final_row[c]), 0.0) << "offset " << c;
  EXPECT_EQ(final_row[5], "1") << "the DCS's controller in control";
  EXPECT_EQ(cl.uc[0].back(), static_cast<double>(0.1F)) << "uc: the DCS's controller output";
  EXPECT_EQ(cl.uc[1].back(), static_cast<double>(-0.05F));
  EXPECT_EQ(cl.r[0].back(), 0.0);
  EXPECT_EQ(cl.r[1].back(), 0.0);
}

// §4: the plant bounds each offset (plant.offset_limit, one per offset register): a write
// beyond it is refused with exception 3 (illegal data value), counted (control +7) and
// reported, and the register keeps its value; a write inside is taken.
TEST_F(ClosedLoopGateway, ThePlantRefusesAnOffsetBeyondItsLimit) {
  loop_config("woodberry2x2", 1502, "--controller " + kPi + " --offsets both");
  {
    std::ifstream in(path("plant.toml"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto at = text.find("controller = ");
    ASSERT_NE(at, std::string::npos) << text;
    text.insert(at, "offset_limit = [0.2, 0.2, 0.5, 0.5]\n");
    std::ofstream(path("plant.toml")) << text;
  }
  const std::uint16_t port = start_plant({"--clock", "lockstep"}, 0);
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  modbus_t* ctx = modbus_new_tcp("127.0.0.1", port);
  ASSERT_EQ(modbus_connect(ctx), 0);
  const auto write_offset = [ctx](int address, float x) {
    std::uint32_t bits;  // float32, word order ABCD (high word first), as the map says
    std::memcpy(&bits, &x, sizeof bits);
    const std::uint16_t r[2] = {static_cast<std::uint16_t>(bits >> 16),
                                static_cast<std::uint16_t>(bits & 0xFFFFU)};
    return modbus_write_registers(ctx, address, 2, r);
  };
  EXPECT_EQ(write_offset(kOffsets, 0.15F), 2) << "inside ±0.2: taken";
  errno = 0;
  EXPECT_EQ(write_offset(kOffsets + 2, -0.25F), -1) << "beyond ±0.2: refused";
  EXPECT_EQ(errno, EMBXILVAL) << modbus_strerror(errno);
  EXPECT_EQ(write_offset(kOffsets + 4, 0.45F), 2) << "a CV setpoint offset inside ±0.5";
  errno = 0;
  EXPECT_EQ(write_offset(kOffsets + 6, 0.75F), -1) << "a CV setpoint offset beyond ±0.5";
  EXPECT_EQ(errno, EMBXILVAL) << modbus_strerror(errno);
  modbus_close(ctx);
  modbus_free(ctx);
  const std::vector<float> held = plc.offsets();
  ASSERT_EQ(held.size(), 4U);
  EXPECT_EQ(held[0], 0.15F);
  EXPECT_EQ(held[1], 0.0F) << "the refused write left its register as it was";
  EXPECT_EQ(held[2], 0.45F);
  EXPECT_EQ(held[3], 0.0F);
  EXPECT_EQ(plc.holding(407), 2) << "control +7 counts the refused writes";
  const std::string err = plant_->stderr_text();
  EXPECT_NE(err.find("write refused (exception 3, illegal data value): MV u2's test offset = "
                     "-0.25 beyond its limit ±0.2 (plant.offset_limit[1])"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("CV y2's setpoint offset = 0.75 beyond its limit ±0.5"), std::string::npos)
      << err;
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0) << err;  // no heartbeat: no sample logged
}

// loop-config checks the controller against the plant before writing anything.
// GIVEN a closed-loop plan designed for CV setpoint offsets (plan v4, excitation setpoint),
// WHEN the gateway's setpoints are MV offsets (or it runs open loop), THEN it refuses the plan
// before anything is written (exit 3, naming both); with setpoint offsets it streams it.
class SetpointPlan : public ClosedLoopGateway {
 protected:
  fs::path setpoint_plan() {
    const fs::path sp = path("sp.plan");
    const std::string line = std::string(EXCITE_TOOL) +
                             " design -q --plant woodberry2x2 --preset prbsUnc --excitation "
                             "setpoint --limit y1=-2:2 --limit y2=-1:1 -o " +
                             sp.string() + " > " + path("design_sp.out").string();
    EXPECT_TRUE(shell(line)) << line;
    return sp;
  }
};

TEST_F(SetpointPlan, IsRefusedWhereTheSetpointsAreMvOffsets) {
  const fs::path sp = setpoint_plan();

  const std::uint16_t port = start("--offsets mv --output-range 0.5", {"--watchdog-s", "2"});
  auto refused = start_gateway(sp, {"--start", "--clock", "lockstep"});
  EXPECT_EQ(refused->wait(30s).value_or(-1), 3) << refused->err();
  EXPECT_NE(refused->err().find("plan excitation = setpoint, expected mv or open_loop"),
            std::string::npos)
      << refused->err();
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  EXPECT_TRUE(all_zero(plc.offsets())) << "nothing written";
}

TEST_F(SetpointPlan, StreamsAsSetpointOffsets) {
  const fs::path sp = setpoint_plan();
  // The plan's r is half of each CV's test limit (y1 ±1, y2 ±0.5): offsets within ±2.
  const std::uint16_t port = start("--offsets setpoint --output-range 2", {"--watchdog-s", "2"});
  auto gw = start_gateway(sp, {"--start", "--clock", "lockstep"});
  ASSERT_EQ(gw->wait(60s).value_or(-1), 0) << gw->err();
  Plc plc(port);
  ASSERT_TRUE(plc.ok());
  EXPECT_TRUE(all_zero(plc.offsets()));
  EXPECT_EQ(plc.mode(), 1) << "the controller in control";
}

TEST_F(ClosedLoopGateway, LoopConfigRefusesABadControllerByName) {
  const fs::path bad = path("bad.toml");
  std::ofstream(bad) << "kind = \"pi\"\nsample_time_min = 1.0\n[model]\nplant = "
                        "\"woodberry2x2\"\n[[pairing]]\ncv = 1\nmv = 1\nkc = -0.375\n"
                        "ti_min = 8.29\n";
  const std::string line = std::string(EXCITE_TOOL) +
                           " loop-config --plant woodberry2x2 --controller " + bad.string() +
                           " -o " + path("out").string() + " 2> " + path("lc.err").string();
  EXPECT_FALSE(shell(line));
  std::ifstream e(path("lc.err"));
  const std::string said((std::istreambuf_iterator<char>(e)), std::istreambuf_iterator<char>());
  EXPECT_NE(said.find("bad.toml: pairing[0].kc = -0.375, expected a gain of the sign of the "
                      "paired G(0) element (12.8)"),
            std::string::npos)
      << said;
  EXPECT_FALSE(fs::exists(path("out") / "gateway.toml")) << "nothing written";
  const std::string can = std::string(EXCITE_TOOL) +
                          " loop-config --plant woodberry2x2 --transport can --controller " + kPi +
                          " -o " + path("out").string() + " 2> " + path("lc.err").string();
  EXPECT_FALSE(shell(can));
}

}  // namespace
}  // namespace excite::test
