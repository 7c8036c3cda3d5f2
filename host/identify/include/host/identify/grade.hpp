// SPDX-License-Identifier: MIT
#pragma once
// Per-element grades A–D: a verdict an engineer can act on, in the manner of the A/B/C/D
// model grades of commercial step-test model builders (Zhu's Tai-Ji, DMC-type tools), which
// grade an element by the error bound of its gain relative to the gain and by whether the
// model explains the data. Here, in this order:
//
//  1. The gain's relative 95 % half-width h = 1.96·SE(K)/|K|:
//       A: h ≤ 0.2   B: h ≤ 0.5   C: h < 1 (the gain's sign is known)   D: otherwise
//     (D is exactly the `weak_gain` status, |K| < 2·SE(K), to rounding of 1.96 vs 2),
//     and D for an element not estimated.
//  2. One grade lower for each residual test the element fails at the 1 % level
//     (residuals.hpp, ResidualTests): its output's residual not white (the row's structure
//     or delay is wrong somewhere), or its output's residual correlated with its own input
//     (this element's dynamics are wrong).
//  3. At most C when a parameter ends on an upper bound (T_p at β·τ_H, T_d at max_delay):
//     the bound, not the data, chose it.
// grade_reason lists each step that lowered the grade.

#include <vector>

#include "host/identify/model.hpp"
#include "host/identify/residuals.hpp"

namespace excite::host {

struct GradeThresholds {
  double a = 0.2;  // largest 1.96·SE(K)/|K| of grade A
  double b = 0.5;  // of grade B
  double c = 1.0;  // below this, C; at or above, D
};

/// Sets grade and grade_reason of every element of `row` (one output) from its estimates
/// and the output's residual tests. `row[i]` is the element of input i.
void grade_row(std::vector<ElementEstimate*> row, const ResidualTests& tests,
               const GradeThresholds& thresholds = {});

}  // namespace excite::host
