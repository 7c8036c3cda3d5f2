// SPDX-License-Identifier: MIT
#pragma once
// Which inputs the data can identify at all: an input must move, and must not be a linear
// combination of the other inputs (then its elements cannot be separated from theirs).

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "host/identify/model.hpp"

namespace excite::host {

struct InputScreen {
  std::vector<ElementStatus> status;  // per input: identified (usable), input_not_moved,
                                      // or input_collinear
  std::vector<std::string> reason;    // "" for usable inputs
  std::vector<int> usable;            // indices of usable inputs, ascending
};

/// Classifies the columns of U (N × n). An input is "not moved" when max|u_i| ≤ 1e-12 of
/// the largest input value; "collinear" when its least-squares residual on the other moving
/// inputs is below 1e-8 of its own norm.
InputScreen screen_inputs(const Eigen::MatrixXd& U);

}  // namespace excite::host
