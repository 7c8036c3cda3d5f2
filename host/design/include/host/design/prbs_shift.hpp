// SPDX-License-Identifier: MIT
#pragma once
// Where a PRBS source starts in its m-sequence (SPEC §1, "cut and shift"): the one place that
// moves it, for another realisation of a design (closed_loop_design.hpp, prbs_phase) and for
// an adaptive test's segments cut from one design (host/adaptive/segments.hpp).

#include <cstdint>

#include "firmware/signal/mseq.hpp"
#include "firmware/signal/recipe.hpp"

namespace excite::host {

/// Starts `prbs` `bits` bits further into its sequence, modulo its period 2^n_r − 1. A source
/// with an invalid register length (no period) is left as it is: the recipe's validation
/// (make_table, the gateway's plan check) refuses it by name.
inline void advance_prbs(signal::PrbsSource& prbs, std::uint64_t bits) {
  const std::uint64_t period = signal::mseq_period(prbs.register_length);
  if (period == 0) return;
  prbs.shift = static_cast<std::uint32_t>((prbs.shift % period + bits % period) % period);
}

}  // namespace excite::host
