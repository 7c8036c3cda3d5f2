// SPDX-License-Identifier: MIT
#pragma once
// What an adaptive test decided, for the record and for the operator (issue 26 §3, §5).
//
// The decision log is JSON Lines, one object per event in the order they happen:
//   {"event":"segment", "index", "first_row", "start_min", "rows", "minutes", "kind":
//    "plain"|"directions", "from_estimate", "weights", "scale", "why"}
//   {"event":"estimate", "index", "after_segment", "samples", "length_min", "colour" (per
//    output, residual_colour.hpp), "singular_values", "singular_value_se", "input_angle_se_deg",
//    "output_angle_se_deg", "sign_uncertain_minors", "grades" (outputs × inputs, "A"–"D"),
//    "need":{"overall", "sigma_n","angle","minor","per_direction"}, "met", "missing",
//    "predicted_stop_min"}
//   {"event":"stop", "criterion_met", "reason", "length_min", "segments", "estimates"}
// (null for a number that is not known; the uncertainties are the stop rule's, widened for
// coloured residuals). The operator's view is the same state as text: the
// latest σ̂_i ± SE and direction angles, the grade matrix, the predicted time to stop, and
// the segment about to go out.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "host/adaptive/adaptive_test.hpp"
#include "host/adaptive/study.hpp"

namespace excite::host {

nlohmann::json segment_event(const SegmentDecision& segment, double sample_time_min);
nlohmann::json estimate_event(const Reestimate& estimate, int index);
nlohmann::json stop_event(const AdaptiveResult& result);

/// The operator's view of the test so far (input and output names label the grade matrix;
/// empty: u1…, y1…). `pending`: the last segment decided has not run yet.
std::string operator_view(const AdaptiveResult& so_far, const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs, bool pending);

/// A study's summary: options, the grid with both shares, both T90s, per seed the outcome.
nlohmann::json study_json(const StudyResult& study);
/// The same as a short table for stdout.
std::string study_text(const StudyResult& study);

}  // namespace excite::host
