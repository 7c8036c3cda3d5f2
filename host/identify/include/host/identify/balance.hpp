// SPDX-License-Identifier: MIT
#pragma once
// Balance of an experiment's outputs (SPEC §5): how evenly the outputs spread over the
// output gain directions. Needs the outputs only (plus W for the projections).

#include <Eigen/Dense>

namespace excite::host {

struct DirectionalBalance {
  Eigen::MatrixXd projections;  // N × p: column i is y_i^×(k) = w_iᵀ y(k) (5.5.2)
  Eigen::VectorXd std_dev;      // standard deviation of each projection (N − 1 divisor)
  double ratio = 0.0;           // min(std_dev) / max(std_dev); 1 = perfectly balanced
};

/// Projections of the outputs Y (N × p) on the output gain directions, the columns of W
/// (p × r, e.g. GainAnalysis::output_directions), (5.5.2). Throws std::invalid_argument
/// when W has not p rows, N < 2, data are not finite, or every projection is constant.
DirectionalBalance directional_balance(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& W);

/// Υ = det(corr([y_1 … y_p])) (6.2.1): 1 for uncorrelated outputs, → 0 when the outputs
/// move together. Throws std::invalid_argument when N < 2, data are not finite, or an
/// output is constant (its correlation is undefined; the message names it).
double output_correlation_determinant(const Eigen::MatrixXd& Y);

}  // namespace excite::host
