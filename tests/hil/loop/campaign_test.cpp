// SPDX-License-Identifier: MIT
// The engineer's main job through the gateway: `excite campaign --loop` streams every one of
// the 17 plans through the real excite-gateway to the real excite-plant and reports on what
// the gateway logged. Its measured data must be the in-process campaign's (the same plans,
// noise and seeds), and it must leave the run logs and models beside the report.
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/hil/loop/loop_fixture.hpp"

namespace excite::test {
namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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
  std::size_t runs = 0;
  for (const auto& entry : fs::directory_iterator(loop / "runs")) {
    const runlog::RunLog log = read_log_or_fail(entry.path() / "run.csv");
    EXPECT_NE(slurp(entry.path() / "run.csv").find("# producer: excite-gateway "),
              std::string::npos)
        << entry.path();
    EXPECT_TRUE(fs::exists(entry.path() / "plant.csv")) << entry.path();
    EXPECT_GT(log.rows(), 100U) << entry.path();
    ++runs;
  }
  EXPECT_EQ(runs, 17U);
  std::size_t models = 0;
  for ([[maybe_unused]] const auto& m : fs::directory_iterator(loop / "models")) ++models;
  EXPECT_EQ(models, 17U);

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
