// SPDX-License-Identifier: MIT
#include <gtest/gtest.h>

#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"

namespace excite::host {
namespace {

class EveryPresetOn : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryPresetOn, DesignsWithinLimitsAndCapacity) {
  const PriorKnowledge prior = case_study(GetParam());
  for (const PresetInfo& preset : presets()) {
    const Design d = design_preset(prior, preset, 0);
    ASSERT_EQ(d.table.cols(), prior.input_count()) << preset.acronym;
    EXPECT_LE(static_cast<std::size_t>(d.table.size()), signal::kTableCapacity) << preset.acronym;
    for (Eigen::Index j = 0; j < d.table.cols(); ++j) {
      const InputSpec& in = prior.inputs[static_cast<std::size_t>(j)];
      EXPECT_LE(d.table.col(j).maxCoeff(), in.max) << preset.acronym;
      EXPECT_GE(d.table.col(j).minCoeff(), in.min) << preset.acronym;
      EXPECT_GT(d.table.col(j).cwiseAbs().maxCoeff(), 0.0)
          << preset.acronym << " input " << j << " never moves";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(LibraryPlants, EveryPresetOn, ::testing::ValuesIn(case_study_plants()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace excite::host
