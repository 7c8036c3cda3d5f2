// SPDX-License-Identifier: MIT
#pragma once
// What the flags rule (host/identify/run_layout.hpp) did to a run, as the JSON of the commands
// that apply it says it (identify, validate, balance); the warning's line is
// host/identify's layout_summary().

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "host/identify/run_layout.hpp"

namespace excite::host::cli {

/// The "data" object of the commands' JSON: what the flags rule did to `runs`.
inline nlohmann::json layout_json(const LayoutReport& r, const std::vector<std::string>& runs) {
  nlohmann::json flags = nlohmann::json::object();
  for (int b = 0; b < 8; ++b) flags[flag_name(b)] = r.rows_with_flag[static_cast<std::size_t>(b)];
  return {{"runs", runs},
          {"rows", r.rows},
          {"scored_rows", r.scored},
          {"flagged_rows_excluded", r.flagged_excluded},
          {"warm_up_rows", r.warm_up},
          {"segments", r.segments},
          {"dropped_segments", r.dropped_segments},
          {"dropped_segment_rows", r.dropped_segment_rows},
          {"discontinuities", r.discontinuities},
          {"rows_with_flag", flags}};
}

}  // namespace excite::host::cli
