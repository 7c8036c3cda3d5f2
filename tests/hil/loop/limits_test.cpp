// SPDX-License-Identifier: MIT
// The limits proved on the plant's side at the boundary: the gateway's setpoint limits and the
// plant's own input limits (plant.toml input_min/input_max, which refuse a write outside with
// exception 3) are set to exactly the plan's extremes (woodberry2x2 prbsUnc: ±0.0694 and
// ±0.0369, read from `excite simulate`'s table, the same signal core as the gateway's). The
// real gateway streams it to the real plant: the run completes, the plant's own log shows
// every input reaching its min and its max (to the float32 register's rounding) and never
// going past, and it ends at the baseline. A gateway that let a value through past its limit
// or a plant limit check off by a rounding would fail here; the fault tests (faults_test)
// only move the inputs 0.04-0.07 inside ±2.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "limits.hpp"
#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// Replaces the first occurrence of `from` after `at` in `text`; returns where it was.
std::size_t replace_after(std::string& text, std::size_t at, const std::string& from,
                          const std::string& to) {
  const std::size_t where = text.find(from, at);
  EXPECT_NE(where, std::string::npos) << from;
  if (where != std::string::npos) text.replace(where, from.size(), to);
  return where;
}

class Limits : public LoopTest {};

TEST_F(Limits, APlanReachingMinAndMaxIsStreamedToTheLimitsAndNeverPast) {
  const std::string plant = "woodberry2x2";
  const fs::path plan = design(plant, "prbsUnc");
  ASSERT_TRUE(shell(std::string(EXCITE_TOOL) + " simulate " + plan.string() + " --plant " + plant +
                    " -o " + path("table.csv").string() + " > /dev/null"));
  const runlog::RunLog table = read_log_or_fail(path("table.csv"));
  ASSERT_EQ(table.du.size(), 2U);
  std::vector<double> lo, hi;
  for (const auto& du : table.du) {
    lo.push_back(*std::min_element(du.begin(), du.end()));
    hi.push_back(*std::max_element(du.begin(), du.end()));
  }
  // The plant's input limits = the plan's extremes (woodberry2x2's baseline is 0).
  loop_config(plant, 1502, "--input-range 1 --period-s 0.005");
  {
    std::string text = slurp(path("plant.toml"));
    replace_after(text, 0, "input_min = [-1.0, -1.0]",
                  "input_min = [" + exact(lo[0]) + ", " + exact(lo[1]) + "]");
    replace_after(text, 0, "input_max = [1.0, 1.0]",
                  "input_max = [" + exact(hi[0]) + ", " + exact(hi[1]) + "]");
    std::ofstream(path("plant.toml")) << text;
  }
  const std::uint16_t port = start_plant({"--clock", "lockstep"}, 0);
  ASSERT_NE(port, 0);
  // The gateway's limits, the same numbers; its port the plant's.
  {
    std::string text = slurp(path("gateway.toml"));
    replace_after(text, 0, "port = 1502", "port = " + std::to_string(port));
    std::size_t at = 0;
    for (std::size_t i = 0; i < 2; ++i) {
      at = replace_after(text, at, "min = -1.0\n", "min = " + exact(lo[i]) + "\n");
      at = replace_after(text, at, "max = 1.0\n", "max = " + exact(hi[i]) + "\n");
    }
    std::ofstream(path("gateway.toml")) << text;
  }
  const std::vector<SetpointLimits> limits = configured_limits(path("gateway.toml"));
  ASSERT_EQ(limits.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(limits[i].min, lo[i]);
    ASSERT_EQ(limits[i].max, hi[i]);
  }

  auto gw = start_gateway(plan, {"--start"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog received = stop_plant_and_read_its_log();
  EXPECT_NE(plant_->stderr_text().find(" 0 writes refused for the input limits"), std::string::npos)
      << plant_->stderr_text();
  expect_plant_inside_configured_limits(received, limits);
  ASSERT_EQ(received.u.size(), 2U);
  for (std::size_t i = 0; i < 2; ++i) {
    const auto [low, high] = std::minmax_element(received.u[i].begin(), received.u[i].end());
    const double step = std::max(std::abs(lo[i]), std::abs(hi[i])) * 0x1p-23;
    EXPECT_NEAR(*low, lo[i], step) << received.input_names[i] << " never reached min";
    EXPECT_NEAR(*high, hi[i], step) << received.input_names[i] << " never reached max";
    EXPECT_LE(std::abs(received.du[i].back()), 1e-9)
        << received.input_names[i] << " is not back at its baseline";
  }
}

}  // namespace
}  // namespace excite::test
