// SPDX-License-Identifier: MIT
#pragma once
// Time-domain evaluation of a multisine and its crest factor (SPEC §1, §5; 4.2.9, 4.3.6).
//
// A multisine of period P samples is x(t) = Σ_k A_k cos(2π i_k t / P + φ_k), t in samples
// (firmware/signal/recipe.hpp `Line`). Lines must satisfy 0 < i_k < P/2 (strictly inside
// the Nyquist band, so every line carries power A_k²/2 on the sample grid) and A_k ≥ 0.

#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "firmware/signal/recipe.hpp"

namespace excite::host::multisine {

using excite::signal::Line;

/// Throws std::invalid_argument naming `what`, the line and the bound when a line has
/// index 0, an index at or beyond the Nyquist line P/2 ("band beyond Nyquist"), a negative
/// or non-finite amplitude, a non-finite phase, or when P = 0 or there are no lines.
void validate_lines(std::span<const Line> lines, std::uint32_t period, std::string_view what);

/// One period of samples x(0 … P−1), evaluated directly (exact cos table), O(lines · P).
std::vector<double> synthesize(std::span<const Line> lines, std::uint32_t period);

/// The band-limited continuous signal at `grid` equally spaced instants of one period,
/// t = m · P / grid, by one inverse real FFT of length `grid` (zero-padded spectrum).
/// Requires grid even and grid > 2 · max index.
std::vector<double> synthesize_on_grid(std::span<const Line> lines, std::uint32_t period,
                                       std::uint32_t grid);

/// Crest factor max|x| / x_RMS of a sequence (4.3.6), RMS about zero (x is a deviation).
/// Throws when the sequence is empty or identically zero.
double crest_factor(std::span<const double> samples);

/// Crest factor on the sample grid of one period (what the gateway streams).
double cf_sampled(std::span<const Line> lines, std::uint32_t period);

/// Default oversampling of `cf_continuous` relative to the period's sample grid.
inline constexpr std::uint32_t kContinuousOversampling = 8;

/// Crest factor of the band-limited continuous signal: evaluated on a grid of at least
/// `oversampling` · P points and at least 32 points per cycle of the highest line (the next
/// power of two), by a zero-padded FFT; the RMS is the exact √(Σ A²/2).
double cf_continuous(std::span<const Line> lines, std::uint32_t period,
                     std::uint32_t oversampling = kContinuousOversampling);

/// Grid used by cf_continuous: next power of two ≥ max(oversampling · P, 32 · max index).
std::uint32_t continuous_grid(std::span<const Line> lines, std::uint32_t period,
                              std::uint32_t oversampling);

}  // namespace excite::host::multisine
