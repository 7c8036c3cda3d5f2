// SPDX-License-Identifier: MIT
#include "firmware/signal/mseq.hpp"

#include <gtest/gtest.h>

#include <cstdint>

namespace excite::signal {
namespace {

class MSequenceOfLength : public ::testing::TestWithParam<int> {};
class MSequenceWalkedOverAPeriod : public ::testing::TestWithParam<int> {};

// Runs the generator through one whole period: the register must come back to its
// start only after exactly 2^n_r − 1 steps, with 2^(n_r−1) ones and 2^(n_r−1) − 1 zeros.
TEST_P(MSequenceWalkedOverAPeriod, HasMaximalPeriodAndBalancedLevels) {
  const int n_r = GetParam();
  MSequence seq(n_r);
  const std::uint32_t period = seq.period();
  ASSERT_EQ(period, (std::uint32_t{1} << n_r) - 1U);

  // The first n_r bits identify the state; the sequence returns to it only after a period.
  std::uint64_t window = 0;
  const std::uint64_t window_mask = (std::uint64_t{1} << n_r) - 1U;
  std::uint64_t ones = 0;
  std::uint64_t first_window = 0;
  std::uint64_t repeats_at = 0;
  for (std::uint64_t k = 0; k < std::uint64_t{period} + static_cast<std::uint64_t>(n_r); ++k) {
    const bool bit = seq.next();
    if (k < period) ones += bit ? 1U : 0U;
    window = ((window << 1U) | (bit ? 1U : 0U)) & window_mask;
    if (k + 1 == static_cast<std::uint64_t>(n_r)) first_window = window;
    if (k + 1 > static_cast<std::uint64_t>(n_r) && repeats_at == 0 && window == first_window) {
      repeats_at = k + 1 - static_cast<std::uint64_t>(n_r);
    }
  }
  EXPECT_EQ(repeats_at, period) << "n_r = " << n_r;
  EXPECT_EQ(ones, std::uint64_t{1} << (n_r - 1));
  EXPECT_EQ(period - ones, (std::uint64_t{1} << (n_r - 1)) - 1U);
}

// The order of the register's transition matrix A is exactly N_s = 2^n_r − 1 when
// A^N_s = I and A^(N_s/p) ≠ I for every prime p dividing N_s — a proof of maximal period
// in O(n_r² log N_s) per power (MSequence::advance), for every n_r up to 31. The state is
// all ones (the start) exactly when the next n_r bits are all ones.
bool at_start_state(MSequence seq) {
  for (int k = 0; k < seq.register_length(); ++k) {
    if (!seq.next()) return false;
  }
  return true;
}

TEST_P(MSequenceOfLength, HasTransitionMatrixOfOrderExactlyTheMaximalPeriod) {
  const int n_r = GetParam();
  const std::uint64_t period = (std::uint64_t{1} << n_r) - 1U;
  MSequence full(n_r);
  full.advance(period - 1U);  // A^(N_s − 1), then one more step: A^N_s
  full.next();
  EXPECT_TRUE(at_start_state(full)) << "A^N_s is not the identity, n_r = " << n_r;
  std::uint64_t rest = period;
  for (std::uint64_t p = 2; p * p <= rest || rest > 1; ++p) {
    if (p * p > rest) p = rest;  // what is left is prime
    if (rest % p != 0) continue;
    while (rest % p == 0) rest /= p;
    MSequence partial(n_r);
    partial.advance(period / p);
    EXPECT_FALSE(at_start_state(partial)) << "A^(N_s/" << p << ") = I, n_r = " << n_r;
  }
}

INSTANTIATE_TEST_SUITE_P(AllRegisterLengths, MSequenceOfLength,
                         ::testing::Range(kMinRegisterLength, kMaxRegisterLength + 1));

// The walk over a whole period (and the count of ones) up to 2^24 − 1 bits; longer
// registers take seconds to a minute each, and the order proof above covers them.
INSTANTIATE_TEST_SUITE_P(RegisterLengthsUpTo24, MSequenceWalkedOverAPeriod,
                         ::testing::Range(kMinRegisterLength, 25));

TEST(MSequence, RejectsRegisterLengthsOutsideTwoToThirtyOne) {
  EXPECT_EQ(mseq_taps(1), 0U);
  EXPECT_EQ(mseq_taps(32), 0U);
  EXPECT_EQ(mseq_period(1), 0U);
  MSequence invalid(40);
  EXPECT_EQ(invalid.period(), 0U);
  EXPECT_FALSE(invalid.next());
}

TEST(MSequence, StartsWithRegisterLengthOnes) {
  MSequence seq(6);
  for (int k = 0; k < 6; ++k) EXPECT_TRUE(seq.next()) << k;
}

TEST(MSequence, AdvanceSkipsExactlyAsManyBitsAsNextWould) {
  for (const int n_r : {2, 3, 6, 8, 13, 20}) {
    for (const std::uint64_t steps : {0ULL, 1ULL, 2ULL, 5ULL, 63ULL, 100ULL, 1000ULL}) {
      MSequence stepped(n_r);
      for (std::uint64_t k = 0; k < steps; ++k) stepped.next();
      MSequence jumped(n_r);
      jumped.advance(steps);
      for (int k = 0; k < 64; ++k) {
        ASSERT_EQ(jumped.next(), stepped.next()) << "n_r " << n_r << " steps " << steps;
      }
    }
  }
}

// The period starts with n_r ones (the all-ones start state): jumping to 3 bits before
// the end of the 2^31 − 1 bit period and stepping 3 bits lands on 31 ones again.
TEST(MSequence, AdvanceNearlyAWholePeriodOfTheLongestRegisterWrapsToItsStart) {
  MSequence seq(31);
  seq.advance(mseq_period(31) - 3U);
  for (int k = 0; k < 3; ++k) seq.next();
  for (int k = 0; k < 31; ++k) ASSERT_TRUE(seq.next()) << k;
}

TEST(MSequence, AdvanceComposes) {
  MSequence once(29);
  once.advance(123'456'789ULL + 987'654'321ULL);
  MSequence twice(29);
  twice.advance(123'456'789ULL);
  twice.advance(987'654'321ULL);
  for (int k = 0; k < 200; ++k) ASSERT_EQ(once.next(), twice.next()) << k;
}

}  // namespace
}  // namespace excite::signal
