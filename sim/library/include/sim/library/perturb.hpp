// SPDX-License-Identifier: MIT
#pragma once
// The perturbed "true" plant of issue 29 §1 (model uncertainty in the design gain): the
// designs keep the nominal plant's prior knowledge, the experiments run on a plant whose
// parameters are each drawn within ±X % of the nominal ones, one draw per Monte Carlo seed:
//   - every element's gain: all terms of element (i, j) times (1 + δ), so G(0)_ij moves by
//     δ (an element built as a sum of terms keeps its shape);
//   - every time constant: each pole and zero factor of every term time-scaled,
//     p(s) → p((1 + δ) s) (a first-order (τs + 1) becomes ((1 + δ)τs + 1); a second-order
//     factor keeps its damping; a repeated factor stays repeated);
//   - every delay: each term's dead time times (1 + δ).
// δ = X/100 · (2r − 1), r uniform in [0, 1) from splitmix64 seeded by the Monte Carlo seed,
// drawn in the order above, element by element row-major: the same seed gives the same plant
// on any machine, thread or shard. Only linear plants (sim/lti transfer matrices) have such
// parameters.

#include <cstdint>
#include <string>

#include "sim/lti/transfer_matrix.hpp"

namespace excite::sim {

/// Largest --perturb (exclusive): a draw of −100 % would zero a gain or a time constant.
inline constexpr double kMaxPerturbPercent = 100.0;

/// `nominal` perturbed as above within ±`percent` % for Monte Carlo seed `seed`; `percent`
/// = 0 gives `nominal` unchanged. Throws std::invalid_argument naming --perturb unless
/// 0 ≤ percent < 100.
sim::TransferMatrix perturbed_plant(const sim::TransferMatrix& nominal, double percent,
                                    std::uint64_t seed);

/// Throws std::invalid_argument "--perturb = X, expected …" unless 0 ≤ X < 100 (finite).
void check_perturb(double percent);

/// X as the shortest text that reads back the same ("12.5").
std::string percent_text(double percent);

/// check_perturb, and a perturbation (percent > 0) only of a linear library plant: otherwise
/// std::invalid_argument "--perturb = X on plant P, expected 0 (only a linear library plant …)".
void check_perturbable(const std::string& plant, double percent);

/// "--perturb = TEXT" parsed: a finite number of percent, 0 ≤ X < 100; throws
/// std::invalid_argument "--perturb = TEXT, expected …" otherwise.
double parse_perturb(const std::string& text);

}  // namespace excite::sim
