// SPDX-License-Identifier: MIT
// Issue 39 §4, with the real programs:
//  - a device refusal (excite-plant --input-range 0.05, exception 3) is not a lost link: no
//    "communication lost" line, no row flagged comm_lost, and the outcome says "the device
//    refused a request" (before: "communication lost … restored", the row flagged comm_lost);
//  - excite-plant --exception-requests 65536 names the range it accepts (before: CLI11's
//    conversion message, no range);
//  - excite loop-config says when it raises --watchdog-s to two tick periods (before: raised
//    from 3 to 10 s without a word);
//  - excite-plant --modbus-rtu whose serial line goes away (socat killed) says so once and
//    waits paced (before: 75-100 % CPU and 1.35 M "rejected frames" in 3 s, nothing said).
#include <signal.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

constexpr const char* kSocat = "/usr/bin/socat";

/// The number before `key` in `text` ("123 rejected frames"), or -1.
long long count_before(const std::string& text, const std::string& key) {
  const std::size_t at = text.find(key);
  if (at == std::string::npos || at == 0) return -1;
  std::size_t from = at - 1;  // the space before the key
  while (from > 0 && std::isdigit(static_cast<unsigned char>(text[from - 1])) != 0) --from;
  return std::stoll(text.substr(from, at - 1 - from));
}

class SmallerItems : public LoopTest {};

TEST_F(SmallerItems, ADeviceRefusalIsNotACommunicationLoss) {
  start_loop(kPlant, "--input-range 2 --period-s 0.005",
             {"--clock", "lockstep", "--input-range", "0.05"});
  const fs::path plan = design(kPlant, "prbsUnc");
  auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 14) << err;
  EXPECT_NE(err.find("(fault: the device refused a request)"), std::string::npos) << err;
  EXPECT_EQ(err.find("communication lost"), std::string::npos) << err;
  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  std::size_t comm_lost = 0;
  for (std::uint32_t f : log.flags) comm_lost += (f & runlog::kCommLost) != 0 ? 1U : 0U;
  EXPECT_EQ(comm_lost, 0U) << err;
  (void)stop_plant_and_read_its_log();
}

TEST_F(SmallerItems, ExceptionRequestsBeyondTheRegisterAreRefusedNamingTheRange) {
  loop_config(kPlant, 1502, "");
  PlantRunner plant({"--config", path("plant.toml").string(), "--modbus-tcp", "127.0.0.1:0",
                     "--exception-requests", "65536"},
                    path("plant65536.stderr"));
  EXPECT_EQ(plant.wait_exit(10s).value_or(-1), 2) << plant.stderr_text();
  EXPECT_NE(plant.stderr_text().find("--exception-requests = 65536, expected a count of "
                                     "requests 0 … 65535"),
            std::string::npos)
      << plant.stderr_text();
}

TEST_F(SmallerItems, LoopConfigSaysWhenItRaisesTheWatchdog) {
  const int rc = run_to_completion(EXCITE_TOOL,
                                   {"loop-config", "--plant", kPlant, "--period-s", "5",
                                    "--watchdog-s", "3", "-o", tmp_.path().string()},
                                   path("loop-config.out"));
  const std::string out = slurp(path("loop-config.out"));
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("--watchdog-s 3 raised to 10 s: at least two tick periods of 5 s"),
            std::string::npos)
      << out;
  EXPECT_NE(slurp(path("plant.toml")).find("watchdog_s = 10"), std::string::npos);
}

TEST_F(SmallerItems, AnRtuPlantWhoseSerialLineGoesAwaySaysSoAndWaitsPaced) {
  if (!fs::exists(kSocat)) GTEST_SKIP() << "socat is not installed (Debian: socat)";
  const fs::path plant_end = path("plant-tty");
  const fs::path other_end = path("gateway-tty");
  auto socat = std::make_unique<PlantRunner>(
      kSocat,
      std::vector<std::string>{"pty,raw,echo=0,link=" + plant_end.string(),
                               "pty,raw,echo=0,link=" + other_end.string()},
      path("socat.txt"));
  for (int i = 0; i < 100 && !(fs::exists(plant_end) && fs::exists(other_end)); ++i) {
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_TRUE(fs::exists(plant_end)) << socat->stderr_text();
  PlantRunner plant({"--plant", kPlant, "--modbus-rtu", plant_end.string(), "--baud", "38400",
                     "--clock", "lockstep"},
                    path("plant-rtu.txt"));
  ASSERT_TRUE(plant.wait_listening()) << plant.stderr_text();
  socat->stop(SIGTERM);  // the line goes away
  bool said = false;
  for (int i = 0; i < 300 && !said; ++i) {
    said = plant.stderr_text().find("excite-plant: serial line " + plant_end.string() + " lost") !=
           std::string::npos;
    std::this_thread::sleep_for(10ms);
  }
  ASSERT_TRUE(said) << plant.stderr_text();
  std::this_thread::sleep_for(1500ms);  // three reopen attempts' worth
  ASSERT_EQ(plant.stop(SIGTERM).value_or(-1), 0) << plant.stderr_text();
  const std::string err = plant.stderr_text();
  EXPECT_EQ(count_before(err, "serial line losses"), 1) << err;
  const long long rejected = count_before(err, "rejected frames");
  EXPECT_GE(rejected, 0) << err;
  EXPECT_LT(rejected, 10) << err;
}

}  // namespace
}  // namespace excite::test
