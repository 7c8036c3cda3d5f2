// SPDX-License-Identifier: MIT
// `excite campaign --loop --controller FILE` (issue 42 §4), the real processes: a two-design
// woodberry2x2 campaign under the PI of sim/control/examples, every design a setpoint
// excitation streamed by the real excite-gateway to the real `excite-plant --controller`.
// Asserted on what it leaves: every run's log is the gateway's run-log v4 (closed loop,
// setpoint excitation, the controller named), the plant's own controller log ends with every
// offset and setpoint offset at zero and the controller in control, and a two-stage model
// per run, listed in summary.json and linked from index.html.
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

#include "loop_fixture.hpp"

namespace excite::test {
namespace {

const std::string kPi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The last `sample` row of the plant's controller log, split at commas.
std::vector<std::string> last_sample(const fs::path& controller_log) {
  std::ifstream in(controller_log);
  std::vector<std::string> last;
  for (std::string line; std::getline(in, line);) {
    if (!line.starts_with("sample,")) continue;
    last.clear();
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) last.push_back(cell);
  }
  return last;
}

class ClosedLoopCampaign : public LoopTest {};

TEST_F(ClosedLoopCampaign, StreamsEveryDesignUnderTheControllerAndIdentifiesEachRun) {
  const fs::path out = path("cl");
  const std::string line =
      std::string(EXCITE_TOOL) + " campaign --plant woodberry2x2 --loop --controller " + kPi +
      " --limit y1=-0.5:0.5 --limit y2=-0.25:0.25 --designs prbsUnc,msGlmSim"
      " --threads 2 -o " +
      out.string() + " > " + path("campaign.out").string() + " 2> " + path("campaign.err").string();
  ASSERT_TRUE(shell(line)) << slurp(path("campaign.err"));
  EXPECT_NE(slurp(path("campaign.out")).find((out / "index.html").string()), std::string::npos);
  const auto summary = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["through_the_gateway"], true);
  EXPECT_EQ(summary["excitation"], "setpoint");
  ASSERT_EQ(summary["experiments"].size(), 2U);
  const std::string report = slurp(out / "index.html");
  for (const auto& e : summary["experiments"]) {
    const std::string name = e["name"];
    const fs::path run = out / e["run_log"].get<std::string>();
    const fs::path folder = run.parent_path();
    // The gateway's own log, v4, nothing passed by hand.
    const std::string text = slurp(run);
    EXPECT_EQ(text.substr(0, text.find('\n')), "# excite run log v4") << name;
    EXPECT_NE(text.find("# producer: excite-gateway "), std::string::npos) << name;
    const runlog::RunLog log = read_log_or_fail(run);
    EXPECT_TRUE(log.closed_loop.closed) << name;
    EXPECT_EQ(log.closed_loop.excitation, runlog::Excitation::setpoint) << name;
    EXPECT_EQ(log.closed_loop.controller, "pi woodberry2x2.pi.toml") << name;
    EXPECT_GE(log.rows(), 945U) << name;
    EXPECT_EQ(e["rows"], log.rows()) << name;
    // The plant's side: every offset (o_u1, o_u2) and setpoint offset (ysp_y1, ysp_y2) back
    // at zero, the controller in control, at its last sample.
    const std::vector<std::string> last = last_sample(folder / "controller.csv");
    ASSERT_EQ(last.size(), 14U) << name;
    EXPECT_EQ(last[3], "control") << name;
    for (const std::size_t c : {4U, 5U, 12U, 13U}) EXPECT_EQ(last[c], "0") << name << " " << c;
    // A two-stage model per run.
    const auto model = nlohmann::json::parse(slurp(out / e["model"].get<std::string>()));
    EXPECT_EQ(model["closed_loop"]["method"], "two-stage") << name;
    ASSERT_EQ(model["gain"].size(), 2U) << name;
    EXPECT_GT(model["gain"][0][0].get<double>(), 0.0) << name << ": G11 of Wood–Berry is 12.8";
    EXPECT_LT(model["gain"][1][1].get<double>(), 0.0) << name << ": G22 is −19.4";
    EXPECT_NE(report.find("href=\"" + e["model"].get<std::string>() + "\""), std::string::npos);
  }
}

}  // namespace
}  // namespace excite::test
