// SPDX-License-Identifier: MIT
#pragma once
// Multichannel line allocation (SPEC §2, thesis 4.4.11–4.4.21). Indices are DFT-grid
// lines of the period (ω_i = 2π i / (P T)); channels are numbered j = 1…n in the thesis
// and c = j − 1 here. Every allocation starts with flat amplitudes and Schroeder phases
// (4.4.5) per channel and per shared source, ready for the crest-factor optimiser.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "host/multisine/multisine_set.hpp"

namespace excite::host::multisine {

/// Standard (non-zippered) multichannel multisine: every channel on the same lines
/// first … first + count − 1 with amplitude `amplitude` and the same Schroeder phases, so
/// the channels are identical signals. Meant for sequential designs (SPEC §4, 9–12: one
/// channel at a time); simultaneous designs use zippered_set, whose channels are orthogonal.
MultisineSet standard_set(std::uint32_t channels, std::uint32_t period, std::uint32_t first_index,
                          std::uint32_t line_count, double amplitude);

struct ZipperedLayout {
  std::uint32_t channels = 1;   // n
  std::uint32_t delta = 0;      // δ: notch, number of low snow slots per channel (4.4.19)
  std::uint32_t lines = 1;      // n_s: band lines per channel
  std::uint32_t high_snow = 0;  // n_a: high snow slots per channel (4.4.20)
  double amplitude = 1.0;       // of every band line
};

/// Zippered spectrum (4.4.18): channel j on lines nδ + j, n(δ+1) + j, …, n(δ+n_s−1) + j;
/// low snow slots j, n + j, …, n(δ−1) + j (4.4.19 as corrected in SPEC §8), high snow
/// slots n(δ+n_s) + j, …, n(δ+n_s+n_a−1) + j (4.4.20). The channels are orthogonal over a
/// period. Throws when a line would reach the Nyquist line P/2.
MultisineSet zippered_set(std::uint32_t period, const ZipperedLayout& layout);

struct ModifiedZipperedOptions {
  /// Besides v_n, give a shared source to every direction i with ξ_i = σ_1/σ_i ≥ this
  /// (SPEC §3: excite every weak direction). 0: only the weakest direction v_n.
  double xi_threshold = 0.0;
  double shared_amplitude = 1.0;  // amplitude of every shared line (the vector d·A has |d| = 1)
};

/// Right singular vectors of G(0) = W Σ Vᵀ (5.2.1) whose directions get shared lines,
/// weakest first: v_n always, then v_i with σ_1/σ_i ≥ xi_threshold (if > 0). Each vector
/// is of unit length, signed so that its largest-magnitude entry is positive.
std::vector<Eigen::VectorXd> weak_input_directions(const Eigen::MatrixXd& gain,
                                                   double xi_threshold);

/// Modified zippered spectrum (4.4.21, Lee & Rivera) with q shared directions: the grid is
/// cut into slots of s = n + q lines; channel j takes s(δ+k) + j and shared source r
/// (direction r, weakest first) takes s(δ+k) + n + r, k = 0 … n_s − 1. With q = 1 this is
/// (n+1)(δ+k) + j uncorrelated and (n+1)(δ+k+1) correlated, exactly 4.4.21. Snow slots as
/// in zippered_set with spacing s. `gain` is the square n×n steady-state gain G(0).
MultisineSet modified_zippered_set(std::uint32_t period, const ZipperedLayout& layout,
                                   const Eigen::MatrixXd& gain,
                                   const ModifiedZipperedOptions& options);

}  // namespace excite::host::multisine
