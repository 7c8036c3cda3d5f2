// SPDX-License-Identifier: MIT
#pragma once
// A recipe's table, generated for the plan tests (a failure to generate fails the test).

#include <gtest/gtest.h>

#include <cstddef>
#include <vector>

#include "firmware/signal/generate.hpp"

namespace excite::plan::testing {

inline std::vector<double> table_of(const signal::Recipe& recipe) {
  std::vector<double> data(std::size_t{recipe.channels} * recipe.samples);
  std::vector<double> scratch(signal::scratch_size(recipe));
  EXPECT_TRUE(signal::generate(recipe, {data.data(), recipe.channels, recipe.samples}, scratch));
  return data;
}

}  // namespace excite::plan::testing
