// SPDX-License-Identifier: MIT
// The engineer's main job through the gateway: `excite campaign --loop` streams every one of
// the 17 plans through the real excite-gateway to the real excite-plant and reports on what
// the gateway logged. Its measured data must be the in-process campaign's (the same plans,
// noise and seeds), and it must leave the run logs and models beside the report.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"
#include "same_run.hpp"

namespace excite::test {
namespace {

class Campaign : public LoopTest {};

TEST_F(Campaign, LoopCampaignStreamsEveryPlanThroughTheGatewayAndReportsTheSameData) {
  const fs::path loop = path("loop");
  const fs::path sim = path("sim");
  const std::string excite(EXCITE_TOOL);
  ASSERT_TRUE(shell(excite + " campaign --plant woodberry2x2 --loop --threads 2 -o " +
                    loop.string() + " > " + path("loop.out").string() + " 2> " +
                    path("loop.err").string()))
      << slurp(path("loop.err"));
  ASSERT_TRUE(shell(excite + " campaign --plant woodberry2x2 --threads 2 -o " + sim.string() +
                    " > /dev/null 2>&1"));

  // The report's path is printed, and every run went through the gateway.
  EXPECT_NE(slurp(path("loop.out")).find((loop / "index.html").string()), std::string::npos);
  EXPECT_TRUE(fs::exists(loop / "index.html"));
  const auto a = nlohmann::json::parse(slurp(loop / "summary.json"));
  const auto b = nlohmann::json::parse(slurp(sim / "summary.json"));
  ASSERT_EQ(a["experiments"].size(), 17U);
  ASSERT_EQ(b["experiments"].size(), 17U);
  // Every run, row by row, as the in-process campaign measured it: the same rows, the same
  // inputs at the same k (du is the plan's table on both sides; a column one row late
  // fails), the outputs to what float32 registers explain (u and y travel as float32:
  // dy to 1e-5 absolute, 1.55e-7 measured on dy of order 1).
  std::size_t runs = 0;
  RunDifference largest;
  for (const auto& entry : fs::directory_iterator(loop / "runs")) {
    const runlog::RunLog log = read_log_or_fail(entry.path() / "run.csv");
    EXPECT_NE(slurp(entry.path() / "run.csv").find("# producer: excite-gateway "),
              std::string::npos)
        << entry.path();
    EXPECT_TRUE(fs::exists(entry.path() / "plant.csv")) << entry.path();
    EXPECT_GT(log.rows(), 100U) << entry.path();
    const fs::path twin = sim / "runs" / entry.path().filename() / "run.csv";
    ASSERT_TRUE(fs::exists(twin)) << twin;
    const RunDifference d =
        expect_same_run(log, read_log_or_fail(twin), 1e-9, 1e-5, entry.path().filename().string());
    largest.du = std::max(largest.du, d.du);
    largest.dy = std::max(largest.dy, d.dy);
    ++runs;
  }
  EXPECT_EQ(runs, 17U);
  std::printf(
      "[ measured ] loop against in-process runs: largest |du| difference %.3g, |dy| %.3g\n",
      largest.du, largest.dy);
  // Every model: each element's status and parameters and each output's fit, to what the
  // float32 rounding of the data moves an output-error fit (measured: fits 1.5e-6 points,
  // parameters 0.009 σ, T_d/T_p2 at a bound 0.019 min; allowed 1e-4, 0.02 σ, 0.05 min).
  std::size_t models = 0;
  double largest_parameter = 0.0;
  for (const auto& m : fs::directory_iterator(loop / "models")) {
    const fs::path twin = sim / "models" / m.path().filename();
    ASSERT_TRUE(fs::exists(twin)) << twin;
    largest_parameter = std::max(
        largest_parameter, expect_same_model(nlohmann::json::parse(slurp(m.path())),
                                             nlohmann::json::parse(slurp(twin)), ModelTolerance{},
                                             m.path().filename().string()));
    ++models;
  }
  EXPECT_EQ(models, 17U);
  std::printf(
      "[ measured ] loop against in-process models: largest parameter difference %.3g sigma\n",
      largest_parameter);

  // The measured outputs' balance (5.5.2, computed on the noisy data) is a plain function of
  // the data: equal to float32 rounding when the gateway's data equal the simulation's.
  for (std::size_t e = 0; e < 17; ++e) {
    const auto& x = a["experiments"][e];
    const auto& y = b["experiments"][e];
    ASSERT_EQ(x["name"], y["name"]);
    EXPECT_EQ(x["samples"], y["samples"]) << x["name"];
    const double rx = x["ratio_noisy"].get<double>();
    const double ry = y["ratio_noisy"].get<double>();
    EXPECT_NEAR(rx, ry, 1e-5 * std::abs(ry)) << x["name"];
    const double ux = x["upsilon_noisy"].get<double>();
    const double uy = y["upsilon_noisy"].get<double>();
    EXPECT_NEAR(ux, uy, 1e-5 * std::abs(uy) + 1e-12) << x["name"];
  }
}

}  // namespace
}  // namespace excite::test
