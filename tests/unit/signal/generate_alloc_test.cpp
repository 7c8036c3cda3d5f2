// SPDX-License-Identifier: MIT
// Proves that generation allocates nothing (STYLE.md practice 5): this executable
// links the counting operator new of tests/support.
#include <gtest/gtest.h>

#include <vector>

#include "counting_new.hpp"
#include "example_recipes.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::signal {
namespace {

TEST(GenerateAllocation, FillsAFourChannelCaseStudyTableWithoutAllocating) {
  // GIVEN a 4-channel, 4080-sample recipe with PRBS, multisine and step sources, and
  // table and scratch storage prepared beforehand
  auto recipe = testing::mixed_case_study_recipe();
  std::vector<double> table(4 * 4080);
  std::vector<double> scratch(scratch_size(*recipe));
  // WHEN the table is generated
  const long before = excite::test::allocations();
  const Status status = generate(*recipe, {table.data(), 4, 4080}, scratch);
  const Status block = generate_block(*recipe, 1234, {table.data(), 4, 100}, scratch);
  const long during = excite::test::allocations() - before;
  // THEN nothing was allocated, and the counter does see allocations
  EXPECT_TRUE(status) << status.message();
  EXPECT_TRUE(block) << block.message();
  EXPECT_EQ(during, 0);
  auto probe = std::make_unique<int>(1);
  EXPECT_GT(excite::test::allocations() - before, during);
}

}  // namespace
}  // namespace excite::signal
