// SPDX-License-Identifier: MIT
#include "firmware/signal/mseq.hpp"

#include <array>

namespace excite::signal {
namespace {

constexpr std::uint32_t taps(std::initializer_list<int> positions) {
  std::uint32_t mask = 0;
  for (const int t : positions) mask |= std::uint32_t{1} << (t - 1);
  return mask;
}

// Primitive trinomials and pentanomials, index n_r (entries 0 and 1 unused).
// Source: Xilinx XAPP052, "Efficient Shift Registers, LFSR Counters, and Long
// Pseudo-Random Sequence Generators", Table 3; each entry is checked to give period
// 2^n_r − 1 by tests/unit/signal/mseq_test.cpp.
constexpr std::array<std::uint32_t, kMaxRegisterLength + 1> kTaps = {
    0U,
    0U,
    taps({2, 1}),
    taps({3, 2}),
    taps({4, 3}),
    taps({5, 3}),
    taps({6, 5}),
    taps({7, 6}),
    taps({8, 6, 5, 4}),
    taps({9, 5}),
    taps({10, 7}),
    taps({11, 9}),
    taps({12, 6, 4, 1}),
    taps({13, 4, 3, 1}),
    taps({14, 5, 3, 1}),
    taps({15, 14}),
    taps({16, 15, 13, 4}),
    taps({17, 14}),
    taps({18, 11}),
    taps({19, 6, 2, 1}),
    taps({20, 17}),
    taps({21, 19}),
    taps({22, 21}),
    taps({23, 18}),
    taps({24, 23, 22, 17}),
    taps({25, 22}),
    taps({26, 6, 2, 1}),
    taps({27, 5, 2, 1}),
    taps({28, 25}),
    taps({29, 27}),
    taps({30, 6, 4, 1}),
    taps({31, 28}),
};

// A linear map of GF(2)^n_r: bit j of the image of x is parity(rows[j] & x).
using BitMatrix = std::array<std::uint32_t, kMaxRegisterLength>;

std::uint32_t apply(const BitMatrix& m, int n, std::uint32_t x) {
  std::uint32_t y = 0;
  for (int j = 0; j < n; ++j) {
    y |= static_cast<std::uint32_t>(__builtin_parity(m[static_cast<std::size_t>(j)] & x)) << j;
  }
  return y;
}

// The map x ↦ a(b(x)).
BitMatrix compose(const BitMatrix& a, const BitMatrix& b, int n) {
  BitMatrix c{};
  for (int j = 0; j < n; ++j) {
    std::uint32_t row = 0;
    for (int k = 0; k < n; ++k) {
      if (((a[static_cast<std::size_t>(j)] >> k) & 1U) != 0U) row ^= b[static_cast<std::size_t>(k)];
    }
    c[static_cast<std::size_t>(j)] = row;
  }
  return c;
}

}  // namespace

std::uint32_t mseq_taps(int n_r) {
  return valid_register_length(n_r) ? kTaps[static_cast<std::size_t>(n_r)] : 0U;
}

MSequence::MSequence(int n_r)
    : n_r_(valid_register_length(n_r) ? n_r : 1),
      taps_(mseq_taps(n_r)),
      mask_(mseq_period(n_r)),
      state_(mask_) {}

void MSequence::advance(std::uint64_t steps) {
  if (mask_ == 0) return;
  steps %= mask_;
  // One step of next(): new bit 0 = parity(state & taps), new bit j = old bit j − 1.
  BitMatrix power{};
  BitMatrix result{};
  power[0] = taps_;
  for (int j = 0; j < n_r_; ++j) {
    if (j > 0) power[static_cast<std::size_t>(j)] = std::uint32_t{1} << (j - 1);
    result[static_cast<std::size_t>(j)] = std::uint32_t{1} << j;
  }
  while (steps != 0) {
    if ((steps & 1U) != 0U) result = compose(power, result, n_r_);
    power = compose(power, power, n_r_);
    steps >>= 1U;
  }
  state_ = apply(result, n_r_, state_);
}

}  // namespace excite::signal
