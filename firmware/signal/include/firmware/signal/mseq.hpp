// SPDX-License-Identifier: MIT
#pragma once
// Maximum-length binary sequences (m-sequences) from a linear feedback shift register,
// the source of every PRBS (SPEC §1, thesis 4.2.2).

#include <cstdint>

namespace excite::signal {

inline constexpr int kMinRegisterLength = 2;
inline constexpr int kMaxRegisterLength = 31;

/// True when n_r is a register length this generator supports (2…31).
constexpr bool valid_register_length(int n_r) {
  return n_r >= kMinRegisterLength && n_r <= kMaxRegisterLength;
}

/// Period N_s = 2^n_r − 1 of the m-sequence of register length n_r (0 when n_r is invalid).
constexpr std::uint32_t mseq_period(int n_r) {
  return valid_register_length(n_r) ? (std::uint32_t{1} << n_r) - 1U : 0U;
}

/// Feedback taps of register length n_r as a bit mask: bit t−1 set for tap t, i.e. the
/// primitive polynomial x^n_r + Σ x^t + 1 over GF(2). 0 when n_r is invalid.
/// The table for every n_r is documented in firmware/signal/README.md.
std::uint32_t mseq_taps(int n_r);

/// Fibonacci LFSR producing one period of 2^n_r − 1 bits, then repeating.
/// Starting from the all-ones state, the first n_r bits are ones. Of every period,
/// 2^(n_r−1) bits are 1 and 2^(n_r−1) − 1 are 0.
class MSequence {
 public:
  /// Precondition: valid_register_length(n_r); an invalid length yields an empty
  /// generator (period() == 0) whose next() always returns false.
  explicit MSequence(int n_r);

  /// The next bit of the sequence.
  bool next() {
    const bool out = ((state_ >> (n_r_ - 1)) & 1U) != 0U;
    const auto feedback = static_cast<std::uint32_t>(__builtin_parity(state_ & taps_));
    state_ = ((state_ << 1U) | feedback) & mask_;
    return out;
  }

  /// Skips `steps` bits at once, as if next() had been called `steps` times, in
  /// O(n_r² log steps) operations (the register's GF(2) transition matrix raised to the
  /// power steps mod period by repeated squaring).
  void advance(std::uint64_t steps);

  std::uint32_t period() const { return mask_; }
  int register_length() const { return n_r_; }

 private:
  int n_r_;
  std::uint32_t taps_;
  std::uint32_t mask_;
  std::uint32_t state_;
};

}  // namespace excite::signal
