// SPDX-License-Identifier: MIT
#pragma once
// Gain-direction analysis of a steady-state gain matrix (SPEC §3, thesis 5.2).

#include <Eigen/Core>

#include <vector>

namespace excite::host {

/// SVD G(0) = W Σ Vᵀ (5.2.1) and what follows from it. Input u = σ_i⁻¹ v_i gives the
/// output w_i of unit length (5.2.2). Sign convention: each w_i has its largest-magnitude
/// component positive (v_i follows), so the directions are reproducible.
struct GainAnalysis {
  Eigen::MatrixXd gain;               // G(0): outputs × inputs
  Eigen::VectorXd singular_values;    // σ_1 ≥ σ_2 ≥ … ≥ σ_r ≥ 0
  Eigen::MatrixXd input_directions;   // V: inputs × r, column i is v_i
  Eigen::MatrixXd output_directions;  // W: outputs × r, column i is w_i
  Eigen::VectorXd xi;                 // ξ_i = σ_1 / σ_i (inf when σ_i = 0)
  double condition_number = 0.0;      // κ = σ_1 / σ_r (inf when singular)
  Eigen::MatrixXd rga;                // Λ = G ∘ (G⁺)ᵀ; NaN when rank deficient

  /// Indices i (0-based) of the directions with ξ_i ≥ threshold: the weak directions that
  /// need excitation of their own (SPEC §3: not only the weakest one).
  std::vector<int> weak_directions(double xi_threshold = 10.0) const;
};

/// Throws std::invalid_argument when G is empty or has a non-finite entry, naming it.
/// A rank-deficient G is analysed (an identified one may be): its ξ_i and κ are then
/// infinite and its RGA NaN.
GainAnalysis analyse_gain(const Eigen::MatrixXd& gain);

/// Throws std::invalid_argument when `a` is rank deficient (smallest singular value within
/// rounding of zero: some direction cannot be reached), for designs that need V·Σ⁻¹.
void require_full_rank(const GainAnalysis& a);

/// Per-output extremes of the static response G(0)·u(k) over a table (N × inputs): a design
/// checked against output limits before a plant test.
struct OutputExcursion {
  double min = 0.0;
  double max = 0.0;
};
std::vector<OutputExcursion> static_output_excursions(const Eigen::MatrixXd& gain,
                                                      const Eigen::MatrixXd& table);

}  // namespace excite::host
