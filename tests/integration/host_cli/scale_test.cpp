// SPDX-License-Identifier: MIT
// Issue 26 §2: `excite scale` sizes the next segment from the identified model so every CV's
// prediction ± 2σ stays inside its test limits — checked on the plant's side: the true plant
// driven by the scaled plan stays inside the limits the unscaled plan leaves.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "cli_process.hpp"
#include "firmware/runlog/reader.hpp"

namespace {

using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

using excite_cli_test::contains;

// The largest |dy| of output j over the run.
double peak(const std::string& path, std::size_t j) {
  const excite::runlog::ReadResult r = excite::runlog::read_run_log(path);
  EXPECT_TRUE(r.ok()) << path;
  double most = 0.0;
  for (const double v : r.log.dy.at(j)) most = std::max(most, std::abs(v));  // dy[j]: column j
  return most;
}

class Scale : public ExciteCli {
 protected:
  // Wood and Berry's column: a PRBS design, a noisy run, its model.
  void SetUp() override {
    ExciteCli::SetUp();
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code,
        0);
    ASSERT_EQ(excite("simulate " + path("wb.plan") +
                     " --plant woodberry2x2 --noise-var 5e-4 --seed 3 -o " + path("test.csv"))
                  .exit_code,
              0);
    ASSERT_EQ(excite("identify " + path("test.csv") + " -o " + path("model.json")).exit_code, 0);
  }
};

TEST_F(Scale, TheScaledPlanKeepsThePlantInsideTheLimitsTheUnscaledOneLeaves) {
  // The design as it is, on the plant (noise-free): y1 swings beyond ±1.
  ASSERT_EQ(excite("simulate " + path("wb.plan") + " --plant woodberry2x2 -o " + path("full.csv"))
                .exit_code,
            0);
  ASSERT_GT(peak(path("full.csv"), 0), 1.2);

  const Result r = excite("scale " + path("wb.plan") + " --model " + path("model.json") +
                          " --limit y1=-1:1 --limit y2=-1:1 -o " + path("scaled.plan") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  const double scale = j.at("scale").get<double>();
  EXPECT_GT(scale, 0.4);
  EXPECT_LT(scale, 1.0);
  EXPECT_EQ(j.at("binding_output"), "y1");
  EXPECT_EQ(j.at("k_sigma"), 2.0);

  // On the plant's side: the scaled plan keeps both CVs inside ±1 (the model is an estimate:
  // its ±2σ band is what the scale keeps inside, the plant's peak lands within it).
  ASSERT_EQ(
      excite("simulate " + path("scaled.plan") + " --plant woodberry2x2 -o " + path("scaled.csv"))
          .exit_code,
      0);
  const double y1 = peak(path("scaled.csv"), 0), y2 = peak(path("scaled.csv"), 1);
  std::printf("scale %.4f: peaks |dy1| %.4f, |dy2| %.4f (limits 1; unscaled %.4f)\n", scale, y1, y2,
              peak(path("full.csv"), 0));
  EXPECT_LE(y1, 1.0 + 0.01);
  EXPECT_LE(y2, 1.0);
  EXPECT_GT(y1, 0.95);  // and it does not waste the room: the limit binds
}

TEST_F(Scale, ARunWhoseResponseAloneLeavesTheLimitsGetsNoPlan) {
  // Limits so tight that what the test already applied is still beyond them.
  const Result r =
      excite("scale " + path("wb.plan") + " --model " + path("model.json") +
             " --limit y1=-0.01:0.01 --history " + path("test.csv") + " -o " + path("none.plan"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "no plan written: the scale is 0 (the history alone")) << r.out;
  EXPECT_FALSE(std::filesystem::exists(path("none.plan")));
}

TEST_F(Scale, BadLimitsAreRefusedByName) {
  const std::string base =
      "scale " + path("wb.plan") + " --model " + path("model.json") + " -o " + path("x.plan");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {" --limit xD=-1:1",
       "--limit \"xD=-1:1\": CV \"xD\", expected one of the model's "
       "outputs: y1, y2"},
      {" --limit y1=-1:abc", "--limit \"y1=-1:abc\": \"abc\", expected a finite number"},
      {" --limit y1=0.5:1",  // named by the option since issue 40 §4 (was: output 1 limits)
       "--limit \"y1=0.5:1\": LOW:HIGH = 0.5:1, expected LOW < 0 < HIGH"},
      {" --limit y1", "--limit \"y1\", expected CV=LOW:HIGH"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = excite(base + args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.out;
    EXPECT_TRUE(contains(r.out, message)) << args << ": " << r.out;
    EXPECT_FALSE(std::filesystem::exists(path("x.plan"))) << args;
  }
}

}  // namespace
