// SPDX-License-Identifier: MIT
// Issue 28 item 3, with the real programs: the plant's watchdog follows the period.
//  - `excite loop-config --period-s 5` writes a plant watchdog of at least two periods and
//    declares it to the gateway (`device.peer_watchdog_s`), which refuses one shorter than two
//    periods (before: watchdog_s = 3, tripping every tick, and nothing to check it by);
//  - the loop at 0.5 s ticks with `--watchdog-s 0.3` asked for: the plant's watchdog never
//    trips during the run (before: it tripped between every two writes while the gateway's
//    log showed the full excitation);
//  - excite-plant free-running with a watchdog shorter than one sample warns at start.
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

// The number on the line `key = NUMBER` of a TOML text (NaN when absent).
double toml_number_of(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\n" + key + " = ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(text.substr(at + key.size() + 4));
}

// "…, 3 watchdog trips, …" in excite-plant's stop line (-1 when absent).
long watchdog_trips(const std::string& err) {
  const std::size_t at = err.find(" watchdog trips");
  if (at == std::string::npos) return -1;
  const std::size_t from = err.rfind(' ', at - 1) + 1;
  return std::stol(err.substr(from, at - from));
}

class WatchdogPeriod : public LoopTest {};

TEST_F(WatchdogPeriod, LoopConfigWritesAWatchdogOfTwoPeriodsAndTheGatewayChecksIt) {
  loop_config(kPlant, 1502, "--period-s 5");
  const std::string plant_toml = slurp(path("plant.toml"));
  const std::string gateway_toml = slurp(path("gateway.toml"));
  const double watchdog = toml_number_of(plant_toml, "watchdog_s");
  EXPECT_GE(watchdog, 10.0) << plant_toml;
  EXPECT_EQ(toml_number_of(gateway_toml, "peer_watchdog_s"), watchdog) << gateway_toml;

  const fs::path plan = design(kPlant, "prbsUnc");
  const auto dry = [&](const std::string& out) {
    return run_to_completion(
        EXCITE_GATEWAY,
        {"--config", path("gateway.toml").string(), "--plan", plan.string(), "--dry-run"},
        path(out));
  };
  EXPECT_EQ(dry("dry.out"), 0) << slurp(path("dry.out"));
  // A declared peer watchdog shorter than two periods is refused by name.
  std::string text = gateway_toml;
  const std::size_t at = text.find("\npeer_watchdog_s = ");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at + 1, text.find('\n', at + 1) - at - 1, "peer_watchdog_s = 3");
  std::ofstream(path("gateway.toml")) << text;
  EXPECT_EQ(dry("short.out"), 2) << slurp(path("short.out"));
  EXPECT_NE(slurp(path("short.out"))
                .find("device.peer_watchdog_s = 3 s, expected at least two tick periods (10 s "
                      "at a period of 5 s)"),
            std::string::npos)
      << slurp(path("short.out"));
}

// The loop at 0.5 s ticks, a 0.3 s watchdog asked for: loop-config makes it 1 s, and the
// plant's watchdog never trips while the gateway writes (3 s of running, then SIGTERM).
TEST_F(WatchdogPeriod, ThePlantsWatchdogNeverTripsBetweenTicks) {
  start_loop(kPlant, "--input-range 2 --period-s 0.5 --watchdog-s 0.3");
  const fs::path plan = design(kPlant, "prbsUnc");
  auto gw = start_gateway(plan, {"--start"});
  std::this_thread::sleep_for(3500ms);
  gw->signal(SIGTERM);
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 6) << gw->err();
  ASSERT_EQ(plant_->stop(SIGTERM).value_or(-1), 0) << plant_->stderr_text();
  EXPECT_EQ(watchdog_trips(plant_->stderr_text()), 0) << plant_->stderr_text();
}

// Free-running with a watchdog shorter than one sample (0.5 s per sample): a warning at start.
TEST_F(WatchdogPeriod, AFreeRunningPlantWarnsOfAWatchdogShorterThanOneSample) {
  loop_config(kPlant, 1502, "");
  start_plant({"--clock", "realtime", "--speedup", "120", "--watchdog-s", "0.3"}, 0);
  std::this_thread::sleep_for(200ms);
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0);
  EXPECT_NE(plant_->stderr_text().find("warning: watchdog 0.3 s is shorter than one sample "
                                       "period (0.5 s)"),
            std::string::npos)
      << plant_->stderr_text();
}

}  // namespace
}  // namespace excite::test
