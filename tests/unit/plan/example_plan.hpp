// SPDX-License-Identifier: MIT
#pragma once
// A complete plan around the mixed case-study recipe (tests/unit/signal/example_recipes.hpp).

#include <memory>

#include "../signal/example_recipes.hpp"
#include "firmware/plan/plan.hpp"

namespace excite::plan::testing {

inline constexpr const char* kDesignName = "mixedCaseStudy";
inline constexpr const char* kProvenance =
    "plant 4x4 column 6.3.1; spec case-study.toml; excite 0.1.0";

inline std::unique_ptr<Plan> example_plan() {
  auto plan = std::make_unique<Plan>();
  plan->recipe = *signal::testing::mixed_case_study_recipe();
  set_text(plan->meta.design_name, kDesignName);
  set_text(plan->meta.provenance, kProvenance);
  plan->meta.created_unix_s = 1'795'000'000;
  plan->meta.sample_time_min = 1.0;
  const char* names[] = {"reflux L", "steam V", "side draw S", "feed F"};
  for (std::uint32_t c = 0; c < 4; ++c) {
    set_text(plan->meta.channels[c].name, names[c]);
    plan->meta.channels[c].min = -10.0 - c;
    plan->meta.channels[c].max = 10.0 + c;
  }
  return plan;
}

}  // namespace excite::plan::testing
