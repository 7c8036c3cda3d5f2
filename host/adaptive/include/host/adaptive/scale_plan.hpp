// SPDX-License-Identifier: MIT
#pragma once
// `excite scale` as one call (issue 26 §2, issue 38 §1): the next segment's plan file scaled
// by predictive amplitude control (amplitude_control.hpp) for a model file, the runs
// already applied and the CV limits. The plan's channels drive the model's inputs by
// position (as the gateway maps them onto its setpoints) at the model's sample time; every
// history run must have the model's channels and sample time. Errors are
// std::invalid_argument naming the file, the field and what was expected.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "host/adaptive/amplitude_control.hpp"

namespace excite::host {

struct ScalePlanRequest {
  std::filesystem::path plan, model;  // the next segment's plan, the current model file
  std::vector<std::string> history;   // run logs already applied, in order
  std::vector<std::string> limits;    // --limit CV=LOW:HIGH texts (cv_limit_text.hpp)
  ScaleOptions options;               // k σ
};

struct ScaledPlan {
  SegmentScale scale;
  std::string binding_output;      // the binding CV's name; "" when none binds
  double sample_time_min = 0.0;    // the model's
  long long history_rows = 0;      // rows of every history run together
  std::optional<plan::Plan> plan;  // the plan with its mix times the scale; none at 0
};

ScaledPlan scale_plan(const ScalePlanRequest& request);

}  // namespace excite::host
