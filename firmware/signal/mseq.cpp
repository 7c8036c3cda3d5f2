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

}  // namespace

std::uint32_t mseq_taps(int n_r) {
  return valid_register_length(n_r) ? kTaps[static_cast<std::size_t>(n_r)] : 0U;
}

MSequence::MSequence(int n_r)
    : n_r_(valid_register_length(n_r) ? n_r : 1),
      taps_(mseq_taps(n_r)),
      mask_(mseq_period(n_r)),
      state_(mask_) {}

}  // namespace excite::signal
