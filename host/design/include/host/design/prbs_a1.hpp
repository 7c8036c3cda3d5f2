// SPDX-License-Identifier: MIT
#pragma once
// Design procedure A1 for PRBS (thesis Table 4.2, SPEC §1): switching time, shift and
// register length from the prior knowledge, each choice explained with its numbers.

#include <cstdint>
#include <string>
#include <vector>

#include "host/design/prior_knowledge.hpp"

namespace excite::host {

struct PrbsDesign {
  double switch_time_min = 0.0;    // T_sw ≤ 2.8 τ_L / α (4.2.3), whole samples
  std::uint32_t hold_samples = 0;  // T_sw / T
  double shift_intervals = 0.0;    // D = 5 τ_H / T_sw (4.2.4), not rounded
  int register_length = 0;         // smallest n_r with N_s ≥ max(2πβτ_H/T_sw, nD) (4.2.5)
  std::uint32_t period_bits = 0;   // N_s = 2^n_r − 1
  // Simultaneous designs use one long sequence as long as the sequential experiment
  // (thesis 6.3: 4 · 63 = 252 ≤ 255 gives n_r = 8 in the case study).
  int long_register_length = 0;  // smallest n_r with 2^n_r − 1 ≥ n · N_s
  std::uint32_t long_period_bits = 0;
  std::uint32_t experiment_samples = 0;  // long period · hold: every design's length
  std::vector<std::string> explanation;  // one line per inequality, with its numbers
};

/// Runs A1 on validated prior knowledge. Throws std::invalid_argument when T_sw would be
/// shorter than one sample, naming the inequality and both sides.
PrbsDesign design_prbs(const PriorKnowledge& prior);

/// Circular shift, in switching intervals, between the cut-and-shift copies of a PRBS of
/// period N_s on `channels` channels (SPEC §1): ⌈D⌉ when channels·⌈D⌉ ≤ N_s, else the
/// maximal equal spacing ⌊N_s / channels⌋.
std::uint32_t channel_shift(double shift_intervals, std::uint32_t period_bits, int channels);

}  // namespace excite::host
