// SPDX-License-Identifier: MIT
#include "firmware/signal/steps.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace excite::signal {
namespace {

StepSource steps_of(std::initializer_list<Segment> segments) {
  StepSource s;
  for (const Segment& seg : segments) s.segments[s.segment_count++] = seg;
  return s;
}

std::vector<double> step_samples(const StepSource& source, std::size_t count,
                                 std::uint64_t t0 = 0) {
  StepGenerator gen(source, t0);
  std::vector<double> out(count);
  for (double& v : out) v = gen.next();
  return out;
}

TEST(Steps, HoldEachLevelForItsLengthThenStayAtZero) {
  const std::vector<double> x = step_samples(steps_of({{1.5, 3}, {-2.0, 2}}), 8);
  EXPECT_EQ(x, (std::vector<double>{1.5, 1.5, 1.5, -2.0, -2.0, 0.0, 0.0, 0.0}));
}

TEST(Steps, SkipZeroLengthSegments) {
  const std::vector<double> x =
      step_samples(steps_of({{9.0, 0}, {1.0, 2}, {7.0, 0}, {-1.0, 1}}), 4);
  EXPECT_EQ(x, (std::vector<double>{1.0, 1.0, -1.0, 0.0}));
}

TEST(Steps, WithoutSegmentsAreZero) {
  EXPECT_EQ(step_samples(StepSource{}, 3), (std::vector<double>{0.0, 0.0, 0.0}));
}

TEST(Steps, StartingAtT0GiveTheSamplesFromT0OfTheWholeSequence) {
  const StepSource source = steps_of({{1.0, 4}, {2.0, 1}, {3.0, 5}});
  const std::vector<double> whole = step_samples(source, 14);
  for (std::uint64_t t0 = 0; t0 < 12; ++t0) {
    const std::vector<double> tail = step_samples(source, 2, t0);
    EXPECT_EQ(tail[0], whole[static_cast<std::size_t>(t0)]) << t0;
    EXPECT_EQ(tail[1], whole[static_cast<std::size_t>(t0 + 1)]) << t0;
  }
}

}  // namespace
}  // namespace excite::signal
