// SPDX-License-Identifier: MIT
// Issue 26 §3, §5: `excite test` runs the adaptive test on a simulated plant and leaves its
// record in a folder — the decision log as it happened, the operator's view, every segment
// as a plan the gateway takes, the whole run log and the last model — and a study over seeds
// judged against the truth.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_process.hpp"
#include "firmware/runlog/reader.hpp"

namespace {

using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

using excite_cli_test::contains;

std::vector<nlohmann::json> json_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(nlohmann::json::parse(line));
  return lines;
}

using AdaptiveTestCommand = ExciteCli;

TEST_F(AdaptiveTestCommand, OneTestLeavesItsDecisionsViewSegmentsRunAndModel) {
  const Result r = excite(
      "test --plant woodberry2x2 --seed 3 --first-scale 0.25 --limit "
      "y1=-0.45:0.45 --limit y2=-0.45:0.45 -o " +
      path("t"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "stopped: the stop rule holds")) << r.out;
  EXPECT_TRUE(contains(r.out, "grades (rows: outputs, columns: inputs)")) << r.out;

  // The decision log: segment 0 first, each estimate after the segment it follows, the stop
  // last; every segment's plan is in segments/.
  const std::vector<nlohmann::json> events = json_lines(path("t/decisions.jsonl"));
  ASSERT_GE(events.size(), 4u);
  EXPECT_EQ(events.front()["event"], "segment");
  EXPECT_EQ(events.front()["kind"], "plain");
  EXPECT_EQ(events.front()["scale"], 0.25);
  EXPECT_EQ(events.back()["event"], "stop");
  EXPECT_EQ(events.back()["criterion_met"], true);
  long long rows = 0;
  int segments = 0;
  for (const nlohmann::json& e : events) {
    if (e["event"] != "segment") continue;
    EXPECT_EQ(e["first_row"], rows);
    rows += e["rows"].get<long long>();
    EXPECT_TRUE(std::filesystem::exists(
        path(("t/segments/segment-" + std::to_string(segments) + ".plan").c_str())));
    if (segments > 0) {
      EXPECT_LT(e["scale"].get<double>(), 1.0) << e.dump();
    }
    ++segments;
  }
  // The run log holds every row, and the plant stayed inside the limits it was given
  // (measured values: noise-free inside ±0.45, the noise adds ≈ 0.07 at 3 σ).
  const excite::runlog::ReadResult log = excite::runlog::read_run_log(path("t/run.csv"));
  ASSERT_TRUE(log.ok());
  ASSERT_EQ(static_cast<long long>(log.log.dy.at(0).size()), rows);
  // Every segment is a plan the gateway reads: `excite inspect` decodes the last one.
  const Result inspect = excite(
      "inspect " + path(("t/segments/segment-" + std::to_string(segments - 1) + ".plan").c_str()));
  EXPECT_EQ(inspect.exit_code, 0) << inspect.out;
  EXPECT_TRUE(contains(inspect.out, "excite test segment")) << inspect.out;
  // The operator's view and the model.
  std::ifstream view(path("t/status.txt"));
  const std::string status((std::istreambuf_iterator<char>(view)), {});
  EXPECT_TRUE(contains(status, "stopped: the stop rule holds")) << status;
  const nlohmann::json model = nlohmann::json::parse(std::ifstream(path("t/model.json")));
  EXPECT_EQ(model["format"], "excite model v2");

  // A folder that holds a test's record is not overwritten.
  const Result again = excite("test --plant woodberry2x2 -o " + path("t"));
  EXPECT_NE(again.exit_code, 0);
  EXPECT_TRUE(contains(again.out, "already holds decisions.jsonl")) << again.out;
}

TEST_F(AdaptiveTestCommand, AStudyJudgesEverySeedAgainstTheTruth) {
  const Result r = excite("test --plant woodberry2x2 --seeds 4 --threads 2 -o " + path("s"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "T90 (stopped with a good model):")) << r.out;
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(path("s/study.json")));
  EXPECT_EQ(s["format"], "excite adaptive study v1");
  ASSERT_EQ(s["per_seed"].size(), 4u);
  EXPECT_EQ(s["grid_min"].size(), s["share_met"].size());
  // σ_n of Wood–Berry's G(0) = [12.8 −18.9; 6.6 −19.4]: σ_n² = (F − √(F² − 4 det²)) / 2,
  // F the squared Frobenius norm.
  const double F = 12.8 * 12.8 + 18.9 * 18.9 + 6.6 * 6.6 + 19.4 * 19.4;
  const double det = 12.8 * -19.4 - -18.9 * 6.6;
  const double sigma_n = std::sqrt((F - std::sqrt(F * F - 4.0 * det * det)) / 2.0);
  for (const nlohmann::json& seed : s["per_seed"]) {
    EXPECT_EQ(seed["stopped_by_rule"], true) << seed.dump();
    EXPECT_EQ(seed["met_at_stop"], true) << seed.dump();
    EXPECT_NEAR(seed["true_sigma_n"].get<double>(), sigma_n, 1e-9 * sigma_n) << seed.dump();
    // What held each estimate, in words; nothing at the one the rule stopped on.
    ASSERT_EQ(seed["estimate_missing"].size(), seed["estimate_min"].size()) << seed.dump();
    EXPECT_EQ(seed["estimate_missing"].back(), "") << seed.dump();
    EXPECT_NE(seed["estimate_missing"].front(), "") << seed.dump();
  }
  // With --perturb each seed has a plant of its own, and says which σ_n it had.
  const Result p =
      excite("test --plant woodberry2x2 --seeds 2 --perturb 10 --threads 2 -o " + path("p"));
  ASSERT_EQ(p.exit_code, 0) << p.out;
  const nlohmann::json ps = nlohmann::json::parse(std::ifstream(path("p/study.json")));
  ASSERT_EQ(ps["per_seed"].size(), 2u);
  const double first = ps["per_seed"][0]["true_sigma_n"].get<double>();
  const double second = ps["per_seed"][1]["true_sigma_n"].get<double>();
  EXPECT_NE(first, second);
  EXPECT_NE(first, sigma_n);
  EXPECT_NEAR(first, sigma_n, 0.5 * sigma_n);  // ±10 % per element moves σ_n, not wildly
}

TEST_F(AdaptiveTestCommand, AStudyWithTheControllerOnSaysSoAndStops) {
  // Issue 41 §4: each segment's r on the CV setpoints of woodberry2x2's example PI.
  const std::string pi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";
  const Result r = excite("test --plant woodberry2x2 --seeds 3 --controller " + pi +
                          " --limit y1=-2:2 --limit y2=-2:2 -o " + path("cl"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "closed loop: r on the CV setpoints under " + pi +
                                  " at 0.5 of the CV limits, the direct estimate"))
      << r.out;
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(path("cl/study.json")));
  EXPECT_EQ(s["closed_loop"]["estimate"], "direct");
  EXPECT_EQ(s["not_run"], 0);
  for (const nlohmann::json& seed : s["per_seed"]) {
    EXPECT_EQ(seed["stopped_by_rule"], true) << seed.dump();
    EXPECT_EQ(seed["met_at_stop"], true) << seed.dump();
    EXPECT_EQ(seed["violated"], false) << seed.dump();
  }
  for (const nlohmann::json& seed : s["per_seed"])
    EXPECT_LT(seed["directional_segments"], seed["segments"]) << "segment 0 plain";
  // The first segment along the prior's output directions: every segment directional.
  const Result o = excite("test --plant woodberry2x2 --seeds 1 --controller " + pi +
                          " --directions output --limit y1=-2:2 --limit y2=-2:2 -o " + path("out"));
  ASSERT_EQ(o.exit_code, 0) << o.out;
  EXPECT_TRUE(contains(o.out, "the first segment along the prior's output directions")) << o.out;
  const nlohmann::json so = nlohmann::json::parse(std::ifstream(path("out/study.json")));
  EXPECT_EQ(so["closed_loop"]["first_segment"], "output directions");
  EXPECT_EQ(so["per_seed"][0]["directional_segments"], so["per_seed"][0]["segments"]);
  EXPECT_EQ(so["per_seed"][0]["met_at_stop"], true);
  // Refused by name, nothing made: one test, an option without the file, no limits for a PI.
  const std::vector<std::pair<std::string, std::string>> bad = {
      {"--controller " + pi, "--seeds = (none) with --controller, expected a study"},
      {"--seeds 2 --method two-stage", "--method requires --controller"},
      {"--seeds 2 --directions output", "--directions requires --controller"},
      {"--seeds 2 --switching plant", "--switching requires --controller"},
      {"--seeds 2 --prbs-phase 3", "--prbs-phase requires --controller"},
      {"--seeds 2 --controller " + pi + " --switching open", "--switching: open not in"},
      {"--seeds 2 --controller " + pi + " --directions input", "--directions: input not in"},
      {"--seeds 2 --controller " + pi,
       "--limit = (none), expected CV test limits for a setpoint excitation"},
  };
  for (const auto& [args, message] : bad) {
    const Result b = excite("test --plant woodberry2x2 " + args + " -o " + path("bad"));
    EXPECT_NE(b.exit_code, 0) << args;
    EXPECT_TRUE(contains(b.out, message)) << args << "\n" << b.out;
    EXPECT_FALSE(std::filesystem::exists(path("bad"))) << args;
  }
}

TEST_F(AdaptiveTestCommand, WithTheControllerOnThePrbsSwitchesAtTheLoopsPace) {
  // colaA under its DMC: the loop follows r along the weakest output direction far slower
  // than the plant's τ_L (15 min), and (4.2.3) takes the loop's time constant; with
  // --switching plant it takes the plant's. One short seed each: the design is what is read.
  const std::string examples = EXCITE_CONTROL_EXAMPLES;
  const auto study = [&](const std::string& plant, const std::string& args, const char* folder) {
    const Result r = excite("test --plant " + plant + " --seeds 1 --max-min 300 --controller " +
                            examples + "/" + plant + ".dmc.toml " + args + " -o " + path(folder));
    EXPECT_EQ(r.exit_code, 0) << r.out;
    const std::string study_json = path(folder) + "/study.json";
    return std::make_pair(r.out, nlohmann::json::parse(std::ifstream(study_json)));
  };
  const auto [loop_text, loop] = study("colaA", "", "loop");
  EXPECT_TRUE(contains(loop_text,
                       "the loop follows a switch of r along the prior's weakest "
                       "output direction in "))
      << loop_text;
  const double tau = loop["closed_loop"]["loop_time_constant_min"];
  EXPECT_TRUE(loop["closed_loop"]["loop_time_constant_reached"]);
  EXPECT_EQ(loop["tau_low_min"], tau);
  const auto [plant_text, plant] = study("colaA", "--switching plant", "plant");
  EXPECT_TRUE(contains(plant_text, "with the plant's tau_L = 15 min")) << plant_text;
  EXPECT_EQ(plant["tau_low_min"], 15.0);
  EXPECT_GT(tau, 4.0 * 15.0);
  EXPECT_GT(loop["switch_time_min"].get<double>(), 4.0 * plant["switch_time_min"].get<double>());
  // alatiqi4x4's DMC follows its weakest direction slower than the plant settles (τ_H 50 min):
  // τ_L stops at τ_H, the design's bound.
  const auto [slow_text, slow] = study("alatiqi4x4", "", "slow");
  EXPECT_GT(slow["closed_loop"]["loop_time_constant_min"].get<double>(), 50.0) << slow_text;
  EXPECT_EQ(slow["tau_low_min"], 50.0);
}

TEST_F(AdaptiveTestCommand, BadOptionsAreRefusedByName) {
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {"--plant nosuch", "plant = \"nosuch\", expected one of: alatiqi4x4"},
      {"--plant woodberry2x2 --limit y9=-1:1",
       "--limit \"y9=-1:1\": CV \"y9\", expected one of "
       "the plant's outputs: y1, y2"},
      {"--plant woodberry2x2 --first-scale 2", "--first-scale"},
      {"--plant woodberry2x2 --perturb abc", "--perturb = abc"},
      {"--plant colaA --perturb 5 --seeds 2",
       "--perturb = 5 on plant colaA, expected 0 (only a linear library plant"},
      // Issue 40 §4: limits that leave the baseline no room, and a length beyond range (it
      // once ran one row and said "-9223372036854775808 min").
      {"--plant woodberry2x2 --limit y1=1:-1",
       "--limit \"y1=1:-1\": LOW:HIGH = 1:-1, expected LOW < 0 < HIGH"},
      {"--plant woodberry2x2 --limit y2=0:0", "--limit \"y2=0:0\": LOW:HIGH = 0:0, expected"},
      {"--plant woodberry2x2 --limit y1=0:1", "--limit \"y1=0:1\": LOW:HIGH = 0:1, expected"},
      {"--plant woodberry2x2 --max-min 1e300",
       "maximum length (--max-min) = 1e+300 min, expected at most 100000000 min"},
      {"--plant woodberry2x2 --seeds 2 --max-min 1e300", "maximum length (--max-min) = 1e+300"},
      // Limits too tight for any excitation: refused before the first row, saying why.
      {"--plant woodberry2x2 --limit y1=-1e-12:1e-12",
       "limits leave room for 6.3e-11 % of the first segment's amplitude (scale 6.3e-13 for the "
       "limits: the prior's G(0) bounds output 1 by 1.59"},
  };
  for (const Case& c : cases) {
    const Result r = excite("test " + c.args + " -o " + path("bad"));
    EXPECT_NE(r.exit_code, 0) << c.args;
    EXPECT_TRUE(contains(r.out, c.message)) << c.args << "\n" << r.out;
    EXPECT_FALSE(std::filesystem::exists(path("bad"))) << c.args << ": nothing is made";
  }
}

}  // namespace

namespace {

// Issue 40 §3: no link is followed when a test writes its folder. A dangling link planted at
// DIR/decisions.jsonl (or any name the test writes) made the test create its target outside
// DIR; the folder is now refused naming it, before any work, and nothing is created.
TEST_F(AdaptiveTestCommand, PlantedLinkInTheFolderIsRefusedNotFollowed) {
  std::filesystem::create_directories(dir_ / "t");
  for (const char* name : {"decisions.jsonl", "status.txt", "run.csv", "model.json"}) {
    SCOPED_TRACE(name);
    std::filesystem::create_symlink(dir_ / "outside", dir_ / "t" / name);
    const Result r = excite("test --plant woodberry2x2 --seed 3 -o " + path("t"));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(r.out, "t: already holds " + std::string(name) +
                                    " (a link), expected a new or empty folder"))
        << r.out;
    EXPECT_FALSE(std::filesystem::exists(dir_ / "outside")) << r.out;
    std::filesystem::remove(dir_ / "t" / name);
  }
  std::filesystem::create_directories(dir_ / "elsewhere");
  std::filesystem::create_directory_symlink(dir_ / "elsewhere", dir_ / "t/segments");
  const Result r = excite("test --plant woodberry2x2 --seed 3 -o " + path("t"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(std::filesystem::is_empty(dir_ / "elsewhere")) << r.out;
}

}  // namespace

namespace {

// Issue 40 §4: limits limit from the first row. The first segment is sized by the prior's
// G(0) (before: at the engineer's amplitude whatever the limits; y1 reached 1.53 against
// ±1e-12 and the run exited 0 without a word); what is measured outside the limits is
// counted per CV, in the decision log, the operator's view and the output, and a CV
// measured outside holds the next segment (outside again after the hold: the test stops).
TEST_F(AdaptiveTestCommand, LimitsBindFromTheFirstRowAndViolationsAreCounted) {
  const Result r = excite(
      "test --plant woodberry2x2 --seed 3 --limit y1=-0.06:0.06 --limit "
      "y2=-0.06:0.06 -o " +
      path("t"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const std::vector<nlohmann::json> events = json_lines(path("t/decisions.jsonl"));
  ASSERT_GE(events.size(), 3u);
  EXPECT_EQ(events.front()["event"], "segment");
  EXPECT_LT(events.front()["scale"].get<double>(), 0.04) << events.front().dump();
  EXPECT_TRUE(contains(events.front()["why"].get<std::string>(),
                       "for the limits: the prior's G(0) bounds output 1 by 1.59"))
      << events.front().dump();
  const nlohmann::json& stop = events.back();
  ASSERT_EQ(stop["event"], "stop");
  ASSERT_EQ(stop["rows_outside_limits"].size(), 2u) << stop.dump();
  const long long outside = stop["rows_outside_limits"][0].get<long long>() +
                            stop["rows_outside_limits"][1].get<long long>();
  EXPECT_GT(outside, 0) << stop.dump();  // the noise (s = 0.022) alone leaves ±0.06 at times
  bool held = false;
  for (const nlohmann::json& e : events) {
    if (e["event"] == "segment" && e["scale"] == 0.0)
      held = held || contains(e["why"].get<std::string>(), "measured outside its limits");
  }
  EXPECT_TRUE(held) << r.out;
  EXPECT_TRUE(contains(r.out, "limits: y1 measured outside its limits in ")) << r.out;
}

}  // namespace
