// SPDX-License-Identifier: MIT
#pragma once
// Crest factor of the band-limited continuous signal behind a multisine table (issue 3 §3):
// the table is what is streamed; between its samples the plant sees the interpolating
// multisine, whose peak can be higher.

#include <vector>

#include "firmware/signal/recipe.hpp"
#include "host/design/table.hpp"

namespace excite::host {

/// Per channel: max over time of the continuous signal (each window of multisine sources
/// evaluated ≥ 8× oversampled by a zero-padded FFT) over the RMS of the channel's table
/// column. NaN for a channel driven by any step or PRBS source, or by nothing.
std::vector<double> continuous_crest_factors(const signal::Recipe& recipe, const Table& table);

}  // namespace excite::host
