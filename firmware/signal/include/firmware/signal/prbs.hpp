// SPDX-License-Identifier: MIT
#pragma once
// PRBS source (4.2.2, SPEC §1): levels ±amplitude (bit 1 → +a), each bit held
// hold_samples, starting `shift` bits into the m-sequence, period (2^n_r − 1) · hold
// samples.
//
//   s(t) = ±a  by bit  b((shift + ⌊t / hold⌋) mod N_s)   of MSequence(n_r)
//
// so the source with shift d is the one with shift 0 advanced by d · hold samples
// ("cut and shift", 6.3.2–6.3.4).

#include <cstdint>

#include "firmware/signal/mseq.hpp"
#include "firmware/signal/recipe.hpp"

namespace excite::signal {

/// Produces s(t0), s(t0 + 1), … of a PRBS source. Precondition: the source is valid
/// (validate()); construction jumps the register ahead in
/// O(n_r² log N_s) operations, whatever shift and t0.
class PrbsGenerator {
 public:
  explicit PrbsGenerator(const PrbsSource& source, std::uint64_t t0 = 0);

  double next() {
    const double value = level_;
    if (++held_ == hold_) {
      held_ = 0;
      level_ = seq_.next() ? amplitude_ : -amplitude_;
    }
    return value;
  }

 private:
  MSequence seq_;
  double amplitude_;
  std::uint32_t hold_;
  std::uint32_t held_ = 0;  // samples of the current bit already produced
  double level_ = 0.0;
};

}  // namespace excite::signal
