// SPDX-License-Identifier: MIT
#pragma once
// What the flags rule (host/identify/run_layout.hpp) did to a run, as the commands that
// apply it say it: one line for the warning, and the "data" object of their JSON
// (identify, validate, balance).

#include <nlohmann/json.hpp>

#include <sstream>
#include <string>
#include <vector>

#include "host/identify/run_layout.hpp"

namespace excite::host::cli {

/// One line: what the flags rule did. Empty when every row was scored in one segment per run.
inline std::string layout_summary(const LayoutReport& r, std::size_t runs) {
  std::ostringstream s;
  s << r.scored << " of " << r.rows << " rows scored in " << r.segments << " segment"
    << (r.segments == 1 ? "" : "s") << " (" << runs << " run" << (runs == 1 ? "" : "s") << ")";
  if (r.flagged_excluded > 0) {
    s << "; " << r.flagged_excluded << " flagged rows excluded (";
    bool first = true;
    for (int b = 0; b < 8; ++b) {
      const Eigen::Index c = r.rows_with_flag[static_cast<std::size_t>(b)];
      if (c == 0) continue;
      s << (first ? "" : ", ") << flag_name(b) << ' ' << c;
      first = false;
    }
    s << ')';
  }
  if (r.discontinuities > 0) s << "; " << r.discontinuities << " discontinuities (plant restart)";
  if (r.skips > 0) s << "; " << r.skips << " skipped-tick rows";
  if (r.warm_up > 0) s << "; " << r.warm_up << " warm-up rows not scored";
  if (r.dropped_segments > 0) {
    s << "; " << r.dropped_segments << " short segments dropped (" << r.dropped_segment_rows
      << " rows)";
  }
  return s.str();
}

inline bool needs_warning(const LayoutReport& r) {
  Eigen::Index flagged = 0;
  for (const Eigen::Index c : r.rows_with_flag) flagged += c;
  return flagged > 0 || r.dropped_segments > 0 || r.warm_up > 0;
}

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
