// SPDX-License-Identifier: MIT
#pragma once
// Phases of a multisine (SPEC §1, thesis 4.4.1 (c)). Every function returns one phase in
// rad per line, in the order of the lines given; lines use the convention of
// firmware/signal/recipe.hpp: amplitude · cos(2π · index · t / period + phase).

#include <cstdint>
#include <span>
#include <vector>

#include "firmware/signal/recipe.hpp"

namespace excite::host::multisine {

using excite::signal::Line;

/// Schroeder phases for general amplitudes (4.4.5), φ_1 = 0:
///   φ_n = −2π Σ_{j<n} ϑ_j (n − j),  ϑ_j = A_j² / Σ A²  (the power fraction of line j),
/// n the position of the line in the given order (lines sorted by index).
/// Throws std::invalid_argument when `amplitudes` is empty, has a negative entry or has
/// no power at all.
std::vector<double> schroeder_phases(std::span<const double> amplitudes);

/// Schroeder phases for N equal amplitudes (4.4.8): φ_n = −π n (n − 1) / N, n = 1…N.
/// Throws std::invalid_argument when N = 0.
std::vector<double> schroeder_phases_equal(std::uint32_t line_count);

/// Linear phases (4.4.3): φ_i = −τ ω_i with ω_i = 2π index_i / period (rad/sample), τ in
/// samples: the signal is an impulse centred at t = τ. Throws when period = 0.
std::vector<double> linear_phases(std::span<const std::uint32_t> indices, std::uint32_t period,
                                  double delay_samples);

/// Independent phases uniform on [0, 2π) from a 64-bit Mersenne twister seeded with
/// `seed`: the same seed gives the same phases on every platform (the mapping from the
/// generator's output to [0, 2π) is done here, not by a std distribution).
std::vector<double> random_phases(std::uint32_t line_count, std::uint64_t seed);

/// Lines from parallel arrays (as a plan or preset file holds them). Throws
/// std::invalid_argument naming `amplitudes` or `phases` when its count differs from the
/// number of indices.
std::vector<Line> make_lines(std::span<const std::uint32_t> indices,
                             std::span<const double> amplitudes, std::span<const double> phases);

/// Schroeder phases (4.4.5) applied to `lines` in place, in the order given.
void apply_schroeder(std::span<Line> lines);

}  // namespace excite::host::multisine
