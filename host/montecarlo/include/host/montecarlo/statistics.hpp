// SPDX-License-Identifier: MIT
#pragma once
// The spread of a figure over seeds and the confidence of a share of seeds.

#include <vector>

namespace excite::host::montecarlo {

/// Median, quartiles and 10–90 % range of the finite values (NaN and ±inf are left out and
/// counted).
/// Quantile q of the n sorted finite values x_0 ≤ … ≤ x_{n−1}: linear interpolation at
/// position q·(n − 1) (Hyndman & Fan type 7, R's default). All NaN when no value is finite.
struct Spread {
  double p10 = 0.0, median = 0.0, p90 = 0.0;
  double p25 = 0.0, p75 = 0.0;  // quartiles (the report's boxes)
  int finite = 0;               // values that entered
  int left_out = 0;             // NaN or infinite values
};
Spread spread_of(std::vector<double> values);

/// Wilson score interval of a share k/n at 95 % (z = 1.959964): bounds in [0, 1].
/// n = 0 gives [0, 1]. Throws std::invalid_argument unless 0 ≤ k ≤ n.
struct Interval {
  double low = 0.0, high = 1.0;
};
Interval wilson95(int k, int n);

}  // namespace excite::host::montecarlo
