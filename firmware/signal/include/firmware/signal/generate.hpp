// SPDX-License-Identifier: MIT
#pragma once
// Recipe → table (recipe.hpp):  table(k, c) = Σ_i mix[c][i] · s_i(k).
//
// Deterministic: the same recipe gives bit-identical tables on every IEEE-754 binary64
// target (the library computes its own sines and cosines and is built with
// -ffp-contract=off; no libm call enters a table value). No heap, no exceptions; the
// caller provides the table and the scratch.

#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware/signal/recipe.hpp"
#include "firmware/signal/status.hpp"
#include "firmware/signal/table.hpp"

namespace excite::signal {

/// Doubles of scratch generate() needs for `recipe`: 3 × the longest multisine period
/// (0 when the recipe has no multisine source).
std::size_t scratch_size(const Recipe& recipe);

/// Fills `table` with the whole table of `recipe`.
/// Errors (nothing useful is written then): the recipe fails validate(recipe); table.channels or
/// table.samples differ from the recipe's (invalid_field); table.data is null; scratch is shorter
/// than scratch_size(recipe) (capacity_exceeded).
Status generate(const Recipe& recipe, TableView table, std::span<double> scratch);

/// Fills `block` with samples [first_sample, first_sample + block.samples) of the table,
/// for a gateway that streams in blocks; equal, value for value, to the same rows of
/// generate(). Errors as generate(), and the block must lie inside [0, recipe.samples).
Status generate_block(const Recipe& recipe, std::uint32_t first_sample, TableView block,
                      std::span<double> scratch);

}  // namespace excite::signal
