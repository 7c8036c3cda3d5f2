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

/// How well the data tell a row's inputs apart (issue 43): inputs that move together
/// (ratio or cascade control, historian data, a controller in the loop) leave the sum of
/// their gains well determined and the split hardly at all.
struct InputSeparation {
  double condition = 1.0;       // κ of the columns' correlation matrix (unit-norm columns)
  Eigen::VectorXd independent;  // per column, √(1 − R²) of its regression on the others: the
                                // part of its movement they do not explain (1: orthogonal)
  Eigen::MatrixXd regression;   // column i: coefficients b of x_i ≈ Σ_k b_k x_k (b_i = 0)
};

/// Of the columns of X (one per input, over the scored rows: the inputs as moved, or as a
/// row's elements filter them). Uncentred, as the gains' regression is. Precondition: no
/// column is zero (screen_inputs() has removed them).
InputSeparation input_separation(const Eigen::MatrixXd& X);

/// The worse of two screens of the same inputs, per input: the smaller independent part,
/// the larger condition number, and the regression of the screen that gave it.
InputSeparation worse_of(const InputSeparation& a, const InputSeparation& b);

}  // namespace excite::host
