// SPDX-License-Identifier: MIT
#pragma once
// A discretised term run as a difference equation in transposed direct form II:
//   y(k) = b0 x(k) + s0,   s_i ← b_{i+1} x(k) − a_{i+1} y(k) + s_{i+1},   s_{order−1} ← b_order x −
//   a_order y
// Coefficients beyond nb/na are zero (DiscreteTerm keeps them so). No allocation.

#include <cstddef>
#include <span>

#include "sim/lti/discretise.hpp"

namespace excite::sim {

/// One sample through `d` with state `s` (order() doubles, zero at rest); returns y(k).
inline double tdf2_step(const DiscreteTerm& d, double* s, double x) {
  const int order = d.order();
  if (order == 0) return d.b[0] * x;
  const double y = d.b[0] * x + s[0];
  for (int i = 0; i + 1 < order; ++i) {
    const auto u = static_cast<std::size_t>(i);
    s[u] = d.b[u + 1] * x - d.a[u + 1] * y + s[u + 1];
  }
  const auto last = static_cast<std::size_t>(order);
  s[last - 1] = d.b[last] * x - d.a[last] * y;
  return y;
}

/// y[k] += H(z) x[k] for k in [0, count), from zero state, ignoring d.delay_samples (the
/// caller offsets the pointers). The whole-experiment fast path.
void tdf2_accumulate(const DiscreteTerm& d, const double* x, double* y, std::size_t count);

/// Terms run side by side (at most this many in one call).
inline constexpr std::size_t kMaxSideBySide = 4;

/// y[k] += Σ_j gains[j]·(H_j(z) x[j])[k] for k in [0, count), terms j = 0 … n−1 (1 ≤ n ≤
/// kMaxSideBySide, the spans of one length), each from zero state, delays ignored as in
/// tdf2_accumulate (x[j][k] is the term's delayed input). Per sample the terms are added to
/// y in the order j = 0, 1, …: rounding for rounding the sums of accumulating each term into
/// zeros z_j by tdf2_accumulate and adding gains[j]·z_j to y in turn (up to the sign of a
/// zero). One recursion alone waits on its own latency; run side by side they overlap.
void tdf2_accumulate_sum(std::span<const DiscreteTerm* const> terms, std::span<const double> gains,
                         std::span<const double* const> x, double* y, std::size_t count);

}  // namespace excite::sim
