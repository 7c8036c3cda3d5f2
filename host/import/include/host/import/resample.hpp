// SPDX-License-Identifier: MIT
#pragma once
// A tag's irregular samples onto the run's uniform grid (issue 13 §1). Never across a gap:
//   - hold: the grid point takes the last sample at or before it; BAD (NaN) when that
//     sample is bad, when there is none, or when it is older than gap_limit_s;
//   - linear: interpolated between the last sample at or before and the first at or after
//     the grid point; BAD when either is bad or missing, or when they are more than
//     gap_limit_s apart (a sample exactly on the grid point is taken as is).

#include <span>
#include <vector>

namespace excite::host::historian {

enum class Resample { hold, linear };

/// Values at grid times `grid_s` (increasing) from samples (time_s increasing, values NaN
/// when bad). Times in seconds.
std::vector<double> resample(std::span<const double> time_s, std::span<const double> values,
                             std::span<const double> grid_s, Resample mode, double gap_limit_s);

/// Median spacing of increasing times (0 for fewer than two).
double median_spacing(std::span<const double> time_s);

}  // namespace excite::host::historian
