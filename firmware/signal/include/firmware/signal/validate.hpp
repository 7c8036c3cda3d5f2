// SPDX-License-Identifier: MIT
#pragma once
// The recipe's contract, checked (README.md "Recipe semantics" lists every rule).

#include <cstddef>
#include <limits>

#include "firmware/signal/recipe.hpp"
#include "firmware/signal/status.hpp"

namespace excite::signal {

/// No capacity limit on the table (the default of validate()).
inline constexpr std::size_t kUnlimited = std::numeric_limits<std::size_t>::max();

/// Ok when `recipe` satisfies every rule of its contract and its table of
/// channels · samples values fits in `table_capacity` values (doubles). Otherwise the
/// first broken rule, in field order, as StatusCode::invalid_field or
/// StatusCode::capacity_exceeded, with a message naming the field, its value and what was
/// expected. Reads nothing outside the used parts (sources < source_count,
/// lines < line_count, segments < segment_count, mix rows < channels).
Status validate(const Recipe& recipe, std::size_t table_capacity = kUnlimited);

}  // namespace excite::signal
