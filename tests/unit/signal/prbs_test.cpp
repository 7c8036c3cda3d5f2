// SPDX-License-Identifier: MIT
#include "firmware/signal/prbs.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "firmware/signal/mseq.hpp"

namespace excite::signal {
namespace {

std::vector<double> prbs_samples(const PrbsSource& source, std::size_t count,
                                 std::uint64_t t0 = 0) {
  PrbsGenerator gen(source, t0);
  std::vector<double> out(count);
  for (double& v : out) v = gen.next();
  return out;
}

TEST(Prbs, HoldsEachMSequenceBitForHoldSamplesWithOneAsPlusAmplitude) {
  const PrbsSource source{6, 2.5, 16, 0};
  const std::vector<double> x = prbs_samples(source, 63 * 16);
  MSequence seq(6);
  for (std::size_t b = 0; b < 63; ++b) {
    const double level = seq.next() ? 2.5 : -2.5;
    for (std::size_t j = 0; j < 16; ++j) ASSERT_EQ(x[b * 16 + j], level) << "bit " << b;
  }
}

// Cut and shift (SPEC §1, 6.3.2–6.3.4): shift d bits = the unshifted signal advanced by
// d · hold samples, circularly over the period N_s · hold.
TEST(Prbs, ShiftedCopyIsTheCircularShiftByShiftTimesHoldSamples) {
  const std::size_t period = 63 * 16;
  const std::vector<double> base = prbs_samples({6, 1.0, 16, 0}, period);
  for (const std::uint32_t d : {1U, 5U, 16U, 31U, 62U}) {
    const std::vector<double> shifted = prbs_samples({6, 1.0, 16, d}, 2 * period);
    for (std::size_t k = 0; k < 2 * period; ++k) {
      ASSERT_EQ(shifted[k], base[(k + d * 16) % period]) << "d = " << d << ", k = " << k;
    }
  }
}

TEST(Prbs, RepeatsWithPeriodOfNsTimesHoldSamples) {
  const std::vector<double> x = prbs_samples({5, 1.0, 3, 7}, 3 * 31 * 3);
  for (std::size_t k = 0; k + 31 * 3 < x.size(); ++k) ASSERT_EQ(x[k], x[k + 31 * 3]) << k;
}

TEST(Prbs, MeanOverOnePeriodIsAmplitudeOverNs) {
  const double a = 0.7;
  const std::vector<double> x = prbs_samples({8, a, 1, 0}, 255);
  double sum = 0.0;
  for (const double v : x) sum += v;
  EXPECT_NEAR(sum / 255.0, a / 255.0, 1e-15);
}

// The ±a m-sequence has the two-valued circular autocorrelation that makes a PRBS
// "pseudo-white": a² at lag 0 and −a²/N_s at every other lag.
TEST(Prbs, CircularAutocorrelationIsMinusASquaredOverNsOffPeak) {
  const double a = 0.7;
  const std::size_t n = 255;
  const std::vector<double> x = prbs_samples({8, a, 1, 0}, n);
  for (std::size_t lag = 0; lag < n; ++lag) {
    double r = 0.0;
    for (std::size_t k = 0; k < n; ++k) r += x[k] * x[(k + lag) % n];
    r /= static_cast<double>(n);
    const double expected = lag == 0 ? a * a : -a * a / static_cast<double>(n);
    ASSERT_NEAR(r, expected, 1e-14) << "lag " << lag;
  }
}

TEST(Prbs, StartingAtT0GivesTheSamplesFromT0OfTheWholeSignal) {
  const PrbsSource source{7, 1.0, 5, 11};
  const std::vector<double> whole = prbs_samples(source, 2000);
  for (const std::uint64_t t0 : {1U, 4U, 5U, 6U, 634U, 1500U}) {
    const std::vector<double> tail = prbs_samples(source, 100, t0);
    for (std::size_t j = 0; j < tail.size(); ++j)
      ASSERT_EQ(tail[j], whole[static_cast<std::size_t>(t0 + j)]) << t0;
  }
}

}  // namespace
}  // namespace excite::signal
