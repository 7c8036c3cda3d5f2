// SPDX-License-Identifier: MIT
#pragma once
// Several channels' multisines on one period (SPEC §2): per channel its own lines, plus
// "shared sources" — scalar multisines applied to all channels along a direction vector
// (the correlated lines of the modified zippered spectrum, 4.4.21). Channel c is
//
//   u_c(t) = Σ_{own lines of c} A cos(2π i t/P + φ) + Σ_s direction_s[c] · s_s(t),
//   s_s(t) = Σ_{lines of s} A cos(2π i t/P + ψ),
//
// so a shared source maps to one recipe source whose mix-matrix column is `direction`.
// `snow` lists, per channel, the grid lines reserved for snow (4.4.19, 4.4.20) that the
// crest-factor optimiser may fill; they are not lines until the optimiser gives them power.

#include <cstdint>
#include <vector>

#include "firmware/signal/recipe.hpp"

namespace excite::host::multisine {

using excite::signal::Line;

struct SharedSource {
  std::vector<Line> lines;        // the scalar multisine s(t)
  std::vector<double> direction;  // unit vector, one entry per channel (a mix column)
};

struct MultisineSet {
  std::uint32_t period = 0;                      // samples
  std::vector<std::vector<Line>> channels;       // own (uncorrelated) lines of each channel
  std::vector<SharedSource> shared;              // correlated lines
  std::vector<std::vector<std::uint32_t>> snow;  // per channel: reserved snow line indices
};

/// Throws std::invalid_argument naming the field when the set is inconsistent: no
/// channels, a line beyond Nyquist, a direction of the wrong size or not of unit length,
/// two lines of one channel (own, shared or snow) on the same index, or more lines than
/// the recipe holds (excite::signal::kMaxLines).
void validate_set(const MultisineSet& set);

/// The lines channel c actually carries: its own lines and every shared line scaled by
/// direction[c] (a negative entry becomes amplitude |d|·A and phase + π), sorted by index.
std::vector<Line> channel_spectrum(const MultisineSet& set, std::size_t channel);

/// Total number of lines the set puts into a recipe (own lines + shared-source lines).
std::size_t recipe_line_count(const MultisineSet& set);

}  // namespace excite::host::multisine
