// SPDX-License-Identifier: MIT
// sim::Plant::step allocates nothing after reset() (STYLE.md practice 5): operator new and
// the malloc family counted over many samples, for a linear plant and both columns.
#include <gtest/gtest.h>

#include <vector>

#include "counting_malloc.hpp"
#include "counting_new.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim {
namespace {

class StepAllocation : public ::testing::TestWithParam<const char*> {};

TEST_P(StepAllocation, StepAllocatesNothingAfterReset) {
  const std::string name = GetParam();
  auto plant = make_plant(name);
  const double a = name == "colaA" ? 0.01 : name == "pilot15" ? 0.0004 : 1.0;
  const int samples = name == "pilot15" ? 40 : 400;
  std::vector<double> du(static_cast<std::size_t>(plant->inputs()));
  std::vector<double> dy(static_cast<std::size_t>(plant->outputs()));
  plant->reset(1.0);
  const long n0 = excite::test::allocations();
  const long m0 = excite::test::mallocs();
  for (int k = 0; k < samples; ++k) {
    for (std::size_t j = 0; j < du.size(); ++j)
      du[j] = ((k / (2 + static_cast<int>(j))) % 2 ? a : -a);
    plant->step(du, dy);
  }
  EXPECT_EQ(excite::test::allocations() - n0, 0) << name << ": operator new during step()";
  if (excite::test::malloc_interposed()) {
    EXPECT_EQ(excite::test::mallocs() - m0, 0) << name << ": malloc during step()";
  }
  EXPECT_NE(dy[0], 0.0) << "the plant must have moved";
}

// Control: the counters see an allocation that the plant makes at reset().
TEST(StepAllocationCounters, CountTheAllocationsOfReset) {
  auto plant = make_plant("alatiqi4x4");
  const long n0 = excite::test::allocations();
  const long m0 = excite::test::mallocs();
  plant->reset(1.0);
  EXPECT_GT(excite::test::allocations() - n0 + excite::test::mallocs() - m0, 0);
}

INSTANTIATE_TEST_SUITE_P(OneOfEachKind, StepAllocation,
                         ::testing::Values("alatiqi4x4", "colaA", "pilot15"),
                         [](const auto& param_info) { return std::string(param_info.param); });

}  // namespace
}  // namespace excite::sim
