// SPDX-License-Identifier: MIT
#pragma once
// Multisine synthesis (4.2.9) on the DFT grid of a P-sample period:
//
//   s(t) = Σ_l A_l · cos(2π · i_l · t / P + φ_l)
//        = Σ_l (A_l cos φ_l) · C[(i_l · t) mod P] − (A_l sin φ_l) · S[(i_l · t) mod P]
//
// with C[m] = cos(2π m / P), S[m] = sin(2π m / P) tabulated once per period in scratch,
// interleaved (C[0], S[0], C[1], S[1], …: one cache line per lookup), with exact integer
// phase reduction (trig.hpp), so a period costs P table entries plus L · P multiply-adds
// and no libm call.

#include <cstdint>
#include <span>

#include "firmware/signal/recipe.hpp"
#include "firmware/signal/status.hpp"

namespace excite::signal {

/// Tabulates unit_circle[2m] = cos(2π m / P), unit_circle[2m + 1] = sin(2π m / P) for
/// m < P = unit_circle.size() / 2.
void fill_unit_circle(std::span<double> unit_circle);

/// One period s(0 … P−1) of the multisine of `lines` into `period_out` (P =
/// period_out.size()), given the table of fill_unit_circle() for the same P (2P values).
/// Precondition: every line index < P (validate() enforces < P/2). Lines are summed in
/// order, so the result is deterministic.
void synthesize_period(std::span<const Line> lines, std::span<const double> unit_circle,
                       std::span<double> period_out);

}  // namespace excite::signal
