// SPDX-License-Identifier: MIT
// The design's time scales travel with the data (issue 18 §1): README's own path — design,
// loop-config, the real excite-plant, the real excite-gateway, then `excite identify` with
// no option — takes the time-constant bound β·τ_H from the gateway's run log, not from a
// plant name the log does not carry (`alatiqi4x4 (excite-plant)`). Before, identify bounded
// the time constants by the run's length and σ₄, the weak gain this product exists to
// measure, came out 0.635: 3.9× the true 0.1635 (SPEC §7).
#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>
#include <string>

#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

class TimeScales : public LoopTest {
 protected:
  /// What `excite ARGS` printed (stdout, and stderr when `merge_stderr`) into a file.
  std::string excite(const std::string& args, bool merge_stderr) {
    const fs::path out = path("excite.out");
    shell(std::string(EXCITE_TOOL) + " " + args + " > " + out.string() +
          (merge_stderr ? " 2>&1" : " 2>/dev/null"));
    std::ifstream in(out);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
};

TEST_F(TimeScales, ReadmePathIdentifiesTheWeakGainWithTheBoundTheRunLogCarries) {
  // GIVEN the README's loop for alatiqi4x4 (case-study noise) and a prbsUnc plan
  const fs::path plan = design("alatiqi4x4", "prbsUnc");
  start_loop("alatiqi4x4", "--seed 7");
  // WHEN the gateway streams it in lock-step
  auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(300s);
  ASSERT_TRUE(rc.has_value()) << "the gateway did not finish";
  ASSERT_EQ(*rc, 0) << gw->err();
  const runlog::RunLog plant_log = stop_plant_and_read_its_log();
  const runlog::RunLog gw_log = read_log_or_fail(path("gw.csv"));

  // THEN both logs carry the design's τ_H = 50 min and β = 3 (SPEC §4), and T_sw = 16 min
  // of its PRBS in the gateway's (the plan's) header
  EXPECT_EQ(gw_log.time_scales.tau_high_min, 50.0);
  EXPECT_EQ(gw_log.time_scales.beta, 3.0);
  EXPECT_EQ(gw_log.time_scales.switch_time_min, 16.0);
  EXPECT_EQ(plant_log.time_scales.tau_high_min, 50.0);
  EXPECT_EQ(plant_log.time_scales.beta, 3.0);
  EXPECT_EQ(gw_log.plant, "alatiqi4x4 (excite-plant)");  // no case study by that name

  // AND identify with no option bounds the time constants by 150 min from the log
  const std::string text = excite("identify " + path("gw.csv").string(), true);
  EXPECT_NE(text.find("time constants bounded by 150 min (beta x tau_H of the run log"),
            std::string::npos)
      << text;
  // AND the weak gain σ₄ is near the true 0.1635, not 3.9× it
  const std::string json = excite("identify --json " + path("gw.csv").string(), false);
  const nlohmann::json model = nlohmann::json::parse(json, nullptr, false);
  ASSERT_FALSE(model.is_discarded()) << json;
  ASSERT_TRUE(model["singular_values"].is_array()) << json;
  const double sigma4 = model["singular_values"][3].get<double>();
  EXPECT_NEAR(sigma4, 0.1635, 0.25 * 0.1635);
}

}  // namespace
}  // namespace excite::test
