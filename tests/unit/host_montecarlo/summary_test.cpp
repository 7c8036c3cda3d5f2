// SPDX-License-Identifier: MIT
// The summary from units: bias against spread per element of G(0), shares and T90 per design.
#include <gtest/gtest.h>

#include "host/montecarlo/summary.hpp"

namespace mc = excite::host::montecarlo;

namespace {

// Ten seeds of one design on woodberry2x2 (G(0) = [12.8 −18.9; 6.6 −19.4]): g11 identified
// 1.0 too high in every seed, every element spread by ±0.1 over the seeds; the criterion met
// on the whole run and from 50 % on, except one seed at 75 %.
std::vector<mc::UnitResult> units() {
  const std::vector<double> truth = {12.8, -18.9, 6.6, -19.4};
  std::vector<mc::UnitResult> out;
  for (int s = 0; s < 10; ++s) {
    mc::UnitResult u;
    u.design = "prbsUnc";
    u.number = 4;
    u.seed = static_cast<std::uint64_t>(s + 1);
    u.samples = 1000;
    u.sample_time_min = 1.0;
    const double noise = 0.02 * (s - 4.5);  // ±0.09
    for (std::size_t k = 0; k < 4; ++k) u.gain.push_back(truth[k] + noise + (k == 0 ? 1.0 : 0.0));
    u.singular_values = {30.4, 4.06};
    u.accuracy.met = true;
    for (const int p : {25, 50, 75, 100})
      u.lengths.push_back({p, 10 * p, p == 25 ? false : !(p == 75 && s == 0)});
    out.push_back(u);
  }
  return out;
}

mc::Config config() {
  mc::Config c;
  c.plant = "woodberry2x2";
  c.designs = {"prbsUnc"};
  c.seeds = 10;
  c.noise_variance = 5e-4;
  c.length_step_percent = 25;
  return c;
}

}  // namespace

TEST(Summary, FlagsAnElementWhoseMedianIsOffByMoreThanItsRange) {
  const nlohmann::json s = mc::summary_json(config(), units());
  const nlohmann::json& e = s["designs"][0]["gain_elements"];
  ASSERT_EQ(e.size(), 4U);
  EXPECT_EQ(e[0]["true"], 12.8);
  EXPECT_NEAR(e[0]["median"].get<double>(), 13.8, 1e-12);
  EXPECT_TRUE(e[0]["bias_exceeds_spread"].get<bool>());
  for (std::size_t k = 1; k < 4; ++k) EXPECT_FALSE(e[k]["bias_exceeds_spread"].get<bool>()) << k;
  EXPECT_NE(mc::summary_text(s).find("prbsUnc: g11 13.8 (true 12.8"), std::string::npos)
      << mc::summary_text(s);
}

TEST(Summary, SharesPerLengthWithWilsonIntervalsAndT90FromThenOn) {
  const nlohmann::json s = mc::summary_json(config(), units());
  const nlohmann::json& d = s["designs"][0];
  EXPECT_EQ(d["criterion"]["met"], 10);
  EXPECT_EQ(d["lengths"][1]["share"], 1.0);  // 50 %
  EXPECT_EQ(d["lengths"][2]["share"], 0.9);  // 75 %: one seed fails
  EXPECT_EQ(d["lengths"][2]["minutes"], 750.0);
  EXPECT_NEAR(d["lengths"][2]["wilson95"][0].get<double>(), 0.5958, 5e-5);
  EXPECT_EQ(d["t90"]["percent"], 50);
}

TEST(Summary, RefusesARunWithAMissingSeed) {
  std::vector<mc::UnitResult> u = units();
  u.pop_back();
  EXPECT_THROW(mc::summary_json(config(), u), std::runtime_error);
}
