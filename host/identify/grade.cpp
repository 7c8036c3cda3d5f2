// SPDX-License-Identifier: MIT
#include "host/identify/grade.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace excite::host {
namespace {

Grade lower(Grade g) {
  return g == Grade::D ? Grade::D : static_cast<Grade>(static_cast<int>(g) + 1);
}

void add_reason(std::string& reasons, const std::string& why) {
  reasons += (reasons.empty() ? "" : "; ") + why;
}

}  // namespace

void grade_row(std::vector<ElementEstimate*> row, const ResidualTests& tests,
               const GradeThresholds& thresholds) {
  for (std::size_t i = 0; i < row.size(); ++i) {
    ElementEstimate& e = *row[i];
    e.grade_reason.clear();
    if (!e.estimated()) {
      e.grade = Grade::D;
      e.grade_reason = "not estimated (" + std::string(to_string(e.status)) + ")";
      continue;
    }
    const double h = 1.96 * e.std_error.gain / std::abs(e.value.gain);
    char text[160];
    if (std::isfinite(h) && h <= thresholds.a) {
      e.grade = Grade::A;
    } else {
      e.grade = !std::isfinite(h)   ? Grade::D
                : h <= thresholds.b ? Grade::B
                : h < thresholds.c  ? Grade::C
                                    : Grade::D;
      std::snprintf(text, sizeof text, "gain known to ±%.0f %% (95 %%)", 100.0 * h);
      add_reason(e.grade_reason, std::isfinite(h) ? text : "gain's standard error not known");
    }
    if (!tests.white()) {
      e.grade = lower(e.grade);
      std::snprintf(text, sizeof text, "output residual not white (Q = %.3g > %.3g)",
                    tests.whiteness, tests.whiteness_limit);
      add_reason(e.grade_reason, text);
    }
    const auto input = static_cast<Eigen::Index>(i);
    if (input < tests.independence.size() && !tests.independent_of(input)) {
      e.grade = lower(e.grade);
      std::snprintf(text, sizeof text, "residual correlated with this input (S = %.3g > %.3g)",
                    tests.independence(input), tests.independence_limit);
      add_reason(e.grade_reason, text);
    }
    if (e.on_upper_bound()) {
      if (e.grade < Grade::C) e.grade = Grade::C;
      for (const std::string& b : e.on_bound()) add_reason(e.grade_reason, b);
    }
  }
}

}  // namespace excite::host
