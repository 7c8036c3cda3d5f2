// SPDX-License-Identifier: MIT
// Units and shards: every unit in exactly one shard, whatever N; options checked by name.
#include <gtest/gtest.h>

#include <set>

#include "host/montecarlo/work.hpp"

namespace mc = excite::host::montecarlo;

namespace {
mc::Config config(int seeds) {
  mc::Config c;
  c.plant = "woodberry2x2";
  c.designs = {"prbsUnc", "stepSeq", "msGlmZipm"};
  c.seeds = seeds;
  c.first_seed = 5;
  mc::normalise(c);
  return c;
}
}  // namespace

TEST(Work, DesignsAreCheckedAndPutInTableOrder) {
  const mc::Config c = config(2);
  EXPECT_EQ(c.designs, (std::vector<std::string>{"stepSeq", "prbsUnc", "msGlmZipm"}));
  mc::Config bad = c;
  bad.designs = {"prbsUnk"};
  try {
    mc::normalise(bad);
    FAIL() << "an unknown design was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--designs: prbsUnk, expected one of stepSeq"),
              std::string::npos)
        << e.what();
  }
}

TEST(Work, EveryUnitIsInExactlyOneShard) {
  mc::Config c = config(7);
  const std::vector<mc::Unit> all = mc::all_units(c);
  ASSERT_EQ(all.size(), 21U);
  EXPECT_EQ(all.front().seed, 5U);
  EXPECT_EQ(all.back().seed, 11U);
  for (int n = 1; n <= 25; ++n) {
    std::multiset<long long> seen;
    for (int i = 1; i <= n; ++i) {
      c.shard = {i, n};
      for (const mc::Unit& u : mc::shard_units(c)) seen.insert(u.number);
    }
    ASSERT_EQ(seen.size(), all.size()) << n << " shards";
    for (const mc::Unit& u : all) EXPECT_EQ(seen.count(u.number), 1U) << n << " shards";
  }
}

TEST(Work, ShardIsParsedAndOutOfRangeValuesNamed) {
  EXPECT_EQ(mc::parse_shard("2/3").index, 2);
  EXPECT_EQ(mc::parse_shard("2/3").count, 3);
  for (const char* text : {"0/3", "4/3", "1/0", "3", "a/b", "1/3x", "-1/3", ""}) {
    try {
      mc::parse_shard(text);
      FAIL() << text << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()),
                "--shard = " + std::string(text) + ", expected i/N with 1 <= i <= N <= 100000");
    }
  }
}

TEST(Work, LengthGridEndsAtTheWholeRun) {
  mc::Config c = config(1);
  EXPECT_EQ(mc::length_grid(c).size(), 20U);
  EXPECT_EQ(mc::length_grid(c).front(), 5);
  c.length_step_percent = 30;
  EXPECT_EQ(mc::length_grid(c), (std::vector<int>{30, 60, 90, 100}));
  c.length_step_percent = 0;
  EXPECT_EQ(mc::length_grid(c), (std::vector<int>{100}));
}
