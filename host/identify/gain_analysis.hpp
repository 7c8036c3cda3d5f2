// SPDX-License-Identifier: MIT
#pragma once
// Directional quality of a steady-state gain matrix (SPEC §3, §6): SVD G(0) = W Σ Vᵀ
// (5.2.1), ratios ξ_i = σ_1/σ_i, condition number κ = σ_1/σ_min and the relative gain
// array RGA = G ∘ (G⁻¹)ᵀ (for non-square G with the pseudo-inverse G⁺ in place of G⁻¹).

#include <Eigen/Dense>

namespace excite::host {

struct GainAnalysis {
  Eigen::MatrixXd gain;               // G(0), p × n
  Eigen::VectorXd singular_values;    // σ_1 ≥ … ≥ σ_min(p,n)
  Eigen::VectorXd xi;                 // ξ_i = σ_1 / σ_i (inf when σ_i = 0)
  double condition_number = 0.0;      // σ_1 / σ_min (inf when singular)
  Eigen::MatrixXd output_directions;  // W (p × min(p, n)), columns w_i
  Eigen::MatrixXd input_directions;   // V (n × min(p, n)), columns v_i
  Eigen::MatrixXd rga;                // p × n; NaN when G is singular
};

/// Throws std::invalid_argument when G is empty or not finite.
GainAnalysis analyse_gain(const Eigen::MatrixXd& G);

}  // namespace excite::host
