// SPDX-License-Identifier: MIT
#pragma once
// Starting phase laws for the crest-factor optimisation of channels coupled by shared
// sources (issue 45: the modified zippered design, 4.4.21). The optimiser (guillaume.hpp)
// runs from each start asked for and keeps the best end.

#include <cstddef>

#include "host/multisine/multisine_set.hpp"

namespace excite::host::multisine {

/// Where an optimisation of channels coupled by shared sources starts (issue 45: the
/// modified zippered design, 4.4.21). Every start is optimised the same way; the best end
/// by the aggregate is kept.
enum class StartPhases {
  given,              // the set's own phases (the allocations': Schroeder, 4.4.5, per source)
  channel_schroeder,  // Schroeder (4.4.5) over all the lines each channel carries, its own and
                      // the shared ones at |d_c|·A; a shared line takes its phase from the
                      // channel whose direction entry is largest (where it dominates)
  newman,          // Newman's flat law φ_k = π (k − 1)²/N per source by position (k = 1…N):
                   // Schroeder's 4.4.8 up to a linear phase, so each source shifted in time
                   // against the others
  grid_schroeder,  // 4.4.8 on the whole grid, φ_i = −π i (i − 1)/I by line index i, I the
                   // top index: all channels' lines as one flat multisine, then split
  random,          // uniform phases (random_phases), seed = the start's position in `starts`
};

/// `set` with its own and shared lines' phases set by `law` (amplitudes, directions and snow
/// unchanged); `position` is the start's place in the list (the seed of `random`).
MultisineSet with_start_phases(const MultisineSet& set, StartPhases law, std::size_t position);

}  // namespace excite::host::multisine
