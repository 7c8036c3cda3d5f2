// SPDX-License-Identifier: MIT
#include "firmware/signal/generate.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "example_recipes.hpp"
#include "firmware/signal/prbs.hpp"

namespace excite::signal {
namespace {

using testing::add_prbs;
using testing::add_steps;
using testing::empty_recipe;
using testing::mixed_case_study_recipe;

std::vector<double> table_of(const Recipe& recipe) {
  std::vector<double> data(std::size_t{recipe.channels} * recipe.samples);
  std::vector<double> scratch(scratch_size(recipe));
  const Status status = generate(recipe, {data.data(), recipe.channels, recipe.samples}, scratch);
  EXPECT_TRUE(status) << status.message();
  return data;
}

// GIVEN two PRBS sources shifted by half a period and a 2×2 rotation by θ as the mix
// THEN every row is the rotation of the two source values: table(k) = R(θ) s(k).
TEST(Generate, MixesSourcesRowByRowThroughTheMixMatrix) {
  auto recipe = empty_recipe(2, 63 * 16);
  add_prbs(*recipe, 6, 1.0, 16, 0);
  add_prbs(*recipe, 6, 0.5, 16, 31);
  const double theta = 0.4;
  recipe->mix[0][0] = std::cos(theta);
  recipe->mix[0][1] = -std::sin(theta);
  recipe->mix[1][0] = std::sin(theta);
  recipe->mix[1][1] = std::cos(theta);
  const std::vector<double> table = table_of(*recipe);

  PrbsGenerator s0(recipe->sources[0].prbs);
  PrbsGenerator s1(recipe->sources[1].prbs);
  for (std::size_t k = 0; k < recipe->samples; ++k) {
    const double a = s0.next();
    const double b = s1.next();
    ASSERT_NEAR(table[2 * k], std::cos(theta) * a - std::sin(theta) * b, 1e-15) << k;
    ASSERT_NEAR(table[2 * k + 1], std::sin(theta) * a + std::cos(theta) * b, 1e-15) << k;
  }
}

TEST(Generate, SourcesAreZeroOutsideTheirWindowAndStartAtTheWindowStart) {
  auto recipe = empty_recipe(1, 20);
  add_steps(*recipe, 5, 6, {{2.0, 2}, {-1.0, 10}});
  recipe->mix[0][0] = 3.0;
  const std::vector<double> table = table_of(*recipe);
  const std::vector<double> expected = {0,  0, 0, 0, 0, 6, 6, -3, -3, -3,
                                        -3, 0, 0, 0, 0, 0, 0, 0,  0,  0};
  EXPECT_EQ(table, expected);
}

TEST(Generate, ChannelsWithAZeroMixRowStayZero) {
  auto recipe = empty_recipe(3, 100);
  add_prbs(*recipe, 4, 1.0, 2, 3);
  recipe->mix[0][0] = 1.0;
  recipe->mix[2][0] = -1.0;
  const std::vector<double> table = table_of(*recipe);
  for (std::size_t k = 0; k < 100; ++k) {
    ASSERT_EQ(table[3 * k + 1], 0.0);
    ASSERT_EQ(table[3 * k + 2], -table[3 * k]);
  }
}

TEST(Generate, BlocksReproduceTheRowsOfTheWholeTableBitForBit) {
  const auto recipe = mixed_case_study_recipe();
  const std::vector<double> whole = table_of(*recipe);
  std::vector<double> scratch(scratch_size(*recipe));
  for (const std::uint32_t block_samples : {997U, 1000U, 4080U}) {
    for (std::uint32_t first = 0; first < recipe->samples; first += block_samples) {
      const std::uint32_t n = std::min(block_samples, recipe->samples - first);
      std::vector<double> block(std::size_t{n} * 4);
      ASSERT_TRUE(generate_block(*recipe, first, {block.data(), 4, n}, scratch));
      ASSERT_EQ(0, std::memcmp(block.data(), whole.data() + std::size_t{first} * 4,
                               block.size() * sizeof(double)))
          << "block at " << first;
    }
  }
}

TEST(Generate, RefusesATableOfOtherShapeThanTheRecipe) {
  const auto recipe = mixed_case_study_recipe();
  std::vector<double> data(4 * 4080);
  std::vector<double> scratch(scratch_size(*recipe));
  const Status wrong_channels = generate(*recipe, {data.data(), 2, 4080}, scratch);
  EXPECT_EQ(wrong_channels.code(), StatusCode::invalid_field);
  EXPECT_EQ(std::string(wrong_channels.message()),
            "table.channels = 2, expected the recipe's channels = 4");
  const Status wrong_samples = generate(*recipe, {data.data(), 4, 4000}, scratch);
  EXPECT_EQ(std::string(wrong_samples.message()),
            "table.samples = 4000, expected the recipe's samples = 4080");
}

TEST(Generate, RefusesAScratchShorterThanScratchSize) {
  const auto recipe = mixed_case_study_recipe();
  std::vector<double> data(4 * 4080);
  EXPECT_EQ(scratch_size(*recipe), 3U * 4080U);
  std::vector<double> scratch(3 * 4080 - 1);
  const Status status = generate(*recipe, {data.data(), 4, 4080}, scratch);
  EXPECT_EQ(status.code(), StatusCode::capacity_exceeded);
  EXPECT_EQ(std::string(status.message()),
            "scratch of 12239 doubles, expected ≥ scratch_size(recipe) = 12240");
}

TEST(Generate, RefusesABlockReachingPastTheTable) {
  const auto recipe = mixed_case_study_recipe();
  std::vector<double> data(4 * 100);
  std::vector<double> scratch(scratch_size(*recipe));
  const Status status = generate_block(*recipe, 4000, {data.data(), 4, 100}, scratch);
  EXPECT_EQ(std::string(status.message()),
            "block samples [4000, 4100), expected inside [0, samples = 4080)");
}

TEST(Generate, RefusesAnInvalidRecipeWithValidatesMessage) {
  auto recipe = mixed_case_study_recipe();
  recipe->sources[1].prbs.register_length = 40;
  std::vector<double> data(4 * 4080);
  std::vector<double> scratch(scratch_size(*recipe));
  const Status status = generate(*recipe, {data.data(), 4, 4080}, scratch);
  EXPECT_EQ(std::string(status.message()), "sources[1].prbs.register_length = 40, expected 2…31");
}

TEST(Generate, RefusesATableWithoutStorage) {
  const auto recipe = mixed_case_study_recipe();
  std::vector<double> scratch(scratch_size(*recipe));
  const Status status = generate(*recipe, {nullptr, 4, 4080}, scratch);
  EXPECT_EQ(std::string(status.message()), "table.data = null, expected storage for 16320 values");
}

TEST(Generate, NeedsNoScratchWithoutMultisines) {
  auto recipe = empty_recipe(1, 10);
  add_prbs(*recipe, 3, 1.0, 1, 0);
  recipe->mix[0][0] = 1.0;
  EXPECT_EQ(scratch_size(*recipe), 0U);
  std::vector<double> data(10);
  EXPECT_TRUE(generate(*recipe, {data.data(), 1, 10}, {}));
}

}  // namespace
}  // namespace excite::signal
