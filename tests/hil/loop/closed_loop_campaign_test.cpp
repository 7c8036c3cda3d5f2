// SPDX-License-Identifier: MIT
// `excite campaign --loop --controller FILE` (issue 42 §4), the real processes: a two-design
// woodberry2x2 campaign under the PI of sim/control/examples, every design a setpoint
// excitation streamed by the real excite-gateway to the real `excite-plant --controller`.
// Asserted on what it leaves: every run's log is the gateway's run-log v4 (closed loop,
// setpoint excitation, the controller named), the plant's own controller log ends with every
// offset and setpoint offset at zero and the controller in control, and a two-stage model
// per run, listed in summary.json and linked from index.html.
#include <Eigen/SVD>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "host/design/case_studies.hpp"
#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

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
    // Judged as the open-loop campaign judges its runs (SPEC §6). The balance: under the PI
    // the CVs follow r, PRBS or multisine uncorrelated across CVs at 0.5 and 0.25, so the
    // outputs' projections on the true output directions are nearly as balanced as r
    // (in process 0.58 for prbsUnc, 0.46 for msGlmSim); the open-loop campaign's prbsUnc and
    // msGlmSim on Wood–Berry give 0.22 and 0.27.
    const auto& std_dev = e["balance"]["projection_std"];
    ASSERT_EQ(std_dev.size(), 2U) << name;
    const double ratio = e["balance"]["ratio"].get<double>();
    EXPECT_NEAR(ratio,
                std::min(std_dev[0].get<double>(), std_dev[1].get<double>()) /
                    std::max(std_dev[0].get<double>(), std_dev[1].get<double>()),
                1e-12)
        << name;
    EXPECT_GT(ratio, 0.4) << name;
    // The cross-validation: each model on both runs; over the other run its figures, and the
    // loss against the true plant's fit on that run.
    const auto& crossfit = e["crossfit_percent"];
    ASSERT_EQ(crossfit.size(), 2U) << name;
    const std::size_t own = name == summary["experiments"][0]["name"] ? 0U : 1U;
    const auto& other = summary["experiments"][1U - own];
    const double on_other = crossfit[1U - own].get<double>();
    EXPECT_GT(crossfit[own].get<double>(), 50.0) << name;
    EXPECT_GT(on_other, 50.0) << name;
    EXPECT_DOUBLE_EQ(e["crossfit"]["average"].get<double>(), on_other) << name;
    EXPECT_EQ(e["crossfit"]["worst_on"], other["name"]) << name;
    EXPECT_NEAR(e["crossfit"]["loss_average"].get<double>(),
                other["truth_fit_percent"].get<double>() - on_other, 1e-9)
        << name;
  }
  EXPECT_NE(report.find("<th>balance ratio (Υ)</th>"), std::string::npos);
  // A figure per run, drawn from its run log; the figures' sources are gone.
  for (const auto& e : summary["experiments"]) {
    const std::string svg =
        "figures/" + fs::path(e["run_log"].get<std::string>()).parent_path().filename().string() +
        ".svg";
    EXPECT_NE(report.find("<img src=\"" + svg + "\""), std::string::npos) << svg;
    const std::string drawn = slurp(out / svg);
    EXPECT_NE(drawn.find("<svg"), std::string::npos) << svg;
    EXPECT_NE(drawn.find("</svg>"), std::string::npos) << svg;
    EXPECT_NE(drawn.find(e["name"].get<std::string>() + " under the controller"), std::string::npos)
        << svg;
    EXPECT_LT(drawn.size(), 300'000U) << svg;
  }
  EXPECT_FALSE(fs::exists(out / "figures" / ".gnuplot"));
}

// Without --loop the same campaign runs in process (excite simulate --controller's path):
// GIVEN the same design, noise and seed, THEN its run is the gateway's row by row: the
// setpoints in force are r rounded to float32 (the offset register), and the controller's
// moves uc and the CVs dy agree to 1e-7 — the plant's controller works on that rounded r
// while the in-process one keeps r in double (a multisine's values are not float32 numbers,
// unlike the ±0.25 of a PRBS), so uc inherits a float32 ulp (measured |Δuc| ≤ 7.0e-9,
// |Δdy| ≤ 2.0e-8 on values up to 0.45); a tick of delay would differ by 1e-2 or more.
// msGlmSim keeps the CVs inside their test limits, so the gateway never suspends it (prbsUnc
// does: y1 passes 0.5 with the case study's noise, and its suspended rows differ on purpose).
TEST_F(ClosedLoopCampaign, InProcessTheSameDesignGivesTheGatewaysRun) {
  const std::string common = " campaign --plant woodberry2x2 --controller " + kPi +
                             " --limit y1=-0.5:0.5 --limit y2=-0.25:0.25 --designs msGlmSim -o ";
  ASSERT_TRUE(shell(std::string(EXCITE_TOOL) + common + path("in").string() + " > /dev/null 2> " +
                    path("in.err").string()))
      << slurp(path("in.err"));
  ASSERT_TRUE(shell(std::string(EXCITE_TOOL) + common + path("gw").string() + " --loop > " +
                    "/dev/null 2> " + path("gw.err").string()))
      << slurp(path("gw.err"));
  const fs::path run = fs::path("runs") / "15-msGlmSim" / "run.csv";
  const runlog::RunLog a = read_log_or_fail(path("gw") / run);
  const runlog::RunLog b = read_log_or_fail(path("in") / run);
  EXPECT_NE(slurp(path("in") / run).find("# producer: excite campaign "), std::string::npos);
  ASSERT_TRUE(b.closed_loop.closed);
  ASSERT_EQ(b.rows(), 945U);
  ASSERT_GE(a.rows(), b.rows());
  std::size_t differ = 0;
  double largest = 0.0;
  for (std::size_t k = 0; k < b.rows(); ++k) {
    for (std::size_t c = 0; c < 2; ++c) {
      ASSERT_EQ(a.closed_loop.ysp[c][k],
                static_cast<double>(static_cast<float>(b.closed_loop.r[c][k])))
          << "row " << k << ": the setpoint in force is r through a float32 register";
      for (const double d :
           {a.closed_loop.uc[c][k] - b.closed_loop.uc[c][k], a.dy[c][k] - b.dy[c][k]}) {
        largest = std::max(largest, std::abs(d));
        differ += std::abs(d) > 1e-7 ? 1U : 0U;
      }
    }
  }
  EXPECT_EQ(differ, 0U) << "values of uc and dy differing by more than 1e-7";
  std::printf("[ measured ] in process against through the gateway: largest |duc|, |ddy| %.3g\n",
              largest);
}

// The figure puts r where it was added: an MV dither's r beside the MVs (the run log's r
// channels are then input indices), a setpoint excitation's beside the CVs.
TEST_F(ClosedLoopCampaign, EachRunsFigureDrawsRWhereItWasAdded) {
  for (const std::string excitation : {"mv", "setpoint"}) {
    const fs::path out = path(excitation);
    ASSERT_TRUE(shell(std::string(EXCITE_TOOL) + " campaign --plant woodberry2x2 --controller " +
                      kPi + " --limit y1=-0.5:0.5 --limit y2=-0.25:0.25 --excitation " +
                      excitation + " --designs prbsUnc -o " + out.string() + " > /dev/null 2> " +
                      path("err").string()))
        << slurp(path("err"));
    const std::string svg = slurp(out / "figures" / "04-prbsUnc.svg");
    const bool mv = excitation == "mv";
    EXPECT_EQ(svg.find("r u1") != std::string::npos, mv) << excitation;
    EXPECT_EQ(svg.find("r y1") != std::string::npos, !mv) << excitation;
    EXPECT_EQ(svg.find("the dither r") != std::string::npos, mv) << excitation;
  }
}

// --directions output (issue 41 §2): r is the same preset's signals along the prior's output
// directions, r(k) = c·W s(k). prbsUnc's s is one binary PRBS per channel, so each column of
// Wᵀ r takes two values (±c·a), where the plain design's r, turned the same way, takes four.
TEST_F(ClosedLoopCampaign, OutputDirectionsPutRAlongThePriorsOutputDirections) {
  const std::string common = " campaign --plant woodberry2x2 --controller " + kPi +
                             " --limit y1=-0.5:0.5 --limit y2=-0.25:0.25 --designs prbsUnc";
  const auto values_along_w = [&](const std::string& options, const fs::path& out) {
    EXPECT_TRUE(shell(std::string(EXCITE_TOOL) + common + options + " -o " + out.string() +
                      " > /dev/null 2> " + path("err").string()))
        << slurp(path("err"));
    const runlog::RunLog log = read_log_or_fail(out / "runs" / "04-prbsUnc" / "run.csv");
    EXPECT_EQ(log.closed_loop.r.size(), 2U);
    // W of the case study's prior G(0), the one the design rotates by.
    const Eigen::MatrixXd W = Eigen::JacobiSVD<Eigen::MatrixXd>(
                                  host::case_study("woodberry2x2").gain, Eigen::ComputeFullU)
                                  .matrixU();
    std::vector<std::size_t> counts;
    for (Eigen::Index i = 0; i < 2; ++i) {
      std::vector<double> values;
      for (std::size_t k = 0; k < log.rows(); ++k) {
        const double v = W(0, i) * log.closed_loop.r[0][k] + W(1, i) * log.closed_loop.r[1][k];
        if (std::none_of(values.begin(), values.end(),
                         [&](double seen) { return std::abs(seen - v) <= 1e-9; }))
          values.push_back(v);
      }
      counts.push_back(values.size());
    }
    return counts;
  };
  EXPECT_EQ(values_along_w(" --directions output", path("along")),
            (std::vector<std::size_t>{2, 2}));
  const nlohmann::json summary = nlohmann::json::parse(slurp(path("along") / "summary.json"));
  EXPECT_EQ(summary["directions"], "output");
  EXPECT_NE(slurp(path("along") / "index.html").find("along the prior's output directions"),
            std::string::npos);
  EXPECT_EQ(values_along_w("", path("plain")), (std::vector<std::size_t>{4, 4}));
  // Without a controller there is no r to turn: refused before any work.
  EXPECT_FALSE(shell(std::string(EXCITE_TOOL) +
                     " campaign --plant woodberry2x2 --directions "
                     "output -o " +
                     path("open").string() + " > /dev/null 2> " + path("err").string()));
  EXPECT_NE(slurp(path("err"))
                .find("--limit/--designs/--directions/--switching/--open-loop-report without "
                      "--controller, expected --controller FILE"),
            std::string::npos)
      << slurp(path("err"));
  EXPECT_FALSE(fs::exists(path("open")));
}

// The designs switch at the loop's pace (issue 41 §4; closed_loop_designs.hpp setpoint_pace):
// alatiqi4x4's DMC, on its own model, follows a switch of r along the prior's weakest output
// direction far slower than the plant's τ_L of 12 min, so (4.2.3)'s τ_L becomes the loop's,
// within τ_H = 50 min, and the run's PRBS switches more slowly than with --switching plant.
TEST_F(ClosedLoopCampaign, SetpointDesignsSwitchAtTheLoopsPaceUnlessToldThePlants) {
  const auto campaign = [&](const std::string& switching, const fs::path& out) {
    EXPECT_TRUE(shell(std::string(EXCITE_TOOL) + " campaign --plant alatiqi4x4 --controller " +
                      std::string(EXCITE_CONTROL_EXAMPLES) +
                      "/alatiqi4x4.dmc.toml --limit-fraction 0.1 --designs prbsUnc" + switching +
                      " -o " + out.string() + " > /dev/null 2> " + path("err").string()))
        << slurp(path("err"));
    const std::string log = slurp(out / "runs" / "04-prbsUnc" / "run.csv");
    const std::size_t at = log.find("# switch_time_min: ");
    EXPECT_NE(at, std::string::npos);
    return std::make_pair(nlohmann::json::parse(slurp(out / "summary.json")),
                          std::stod(log.substr(at + 19)));
  };
  const auto [loop, loop_switch] = campaign("", path("loop"));
  EXPECT_EQ(loop["switching"], "loop");
  EXPECT_EQ(loop["loop_time_constant_reached"], true);
  EXPECT_GT(loop["loop_time_constant_min"].get<double>(), 50.0);
  EXPECT_DOUBLE_EQ(loop["tau_low_min"].get<double>(), 50.0);  // the loop's, capped at τ_H
  EXPECT_NE(slurp(path("loop") / "index.html").find("switch at the loop's pace"),
            std::string::npos);
  const auto [plant, plant_switch] = campaign(" --switching plant", path("plant"));
  EXPECT_EQ(plant["switching"], "plant");
  EXPECT_FALSE(plant.contains("loop_time_constant_min"));
  EXPECT_DOUBLE_EQ(plant["tau_low_min"].get<double>(), host::case_study("alatiqi4x4").tau_low_min);
  EXPECT_GT(loop_switch, 3.0 * plant_switch) << loop_switch << " against " << plant_switch;
  for (const auto& summary : {loop, plant})
    EXPECT_EQ(summary["experiments"][0]["rows_mv_limited"], 0) << summary.dump();
  EXPECT_FALSE(shell(std::string(EXCITE_TOOL) +
                     " campaign --plant alatiqi4x4 --switching plant -o " + path("open").string() +
                     " > /dev/null 2> " + path("err").string()));
  EXPECT_NE(slurp(path("err")).find("--switching/--open-loop-report without --controller"),
            std::string::npos)
      << slurp(path("err"));
}

}  // namespace
}  // namespace excite::test
