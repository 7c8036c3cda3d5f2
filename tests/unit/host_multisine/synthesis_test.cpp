// SPDX-License-Identifier: MIT
#include "host/multisine/synthesis.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace excite::host::multisine {
namespace {

std::string message_of(const std::function<void()>& call) {
  try {
    call();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "no exception";
}

TEST(Synthesize, FollowsTheRecipeLineConvention) {
  // amplitude · cos(2π · index · t / period + phase), t in samples.
  const std::vector<Line> lines{{3, 0.7, 0.4}, {5, 1.3, -2.0}};
  const auto x = synthesize(lines, 40);
  for (std::uint32_t t = 0; t < 40; ++t) {
    const double expected = 0.7 * std::cos(2.0 * std::numbers::pi * 3 * t / 40 + 0.4) +
                            1.3 * std::cos(2.0 * std::numbers::pi * 5 * t / 40 - 2.0);
    EXPECT_NEAR(x[t], expected, 1e-12) << "t = " << t;
  }
}

TEST(SynthesizeOnGrid, EqualsTheDirectSumAtEveryGridInstant) {
  const std::vector<Line> lines{{1, 1.0, 0.1}, {4, 0.5, 2.0}, {7, 0.25, -1.0}};
  const auto fine = synthesize_on_grid(lines, 30, 120);  // t = m/4 samples
  for (std::uint32_t m = 0; m < 120; ++m) {
    double expected = 0.0;
    for (const Line& line : lines) {
      expected +=
          line.amplitude * std::cos(2.0 * std::numbers::pi * line.index * m / 120.0 + line.phase);
    }
    EXPECT_NEAR(fine[m], expected, 1e-12) << "m = " << m;
  }
}

TEST(CrestFactor, OfACosineOnItsGridIsSqrtTwo) {
  const std::vector<Line> lines{{1, 2.0, 0.0}};
  EXPECT_NEAR(cf_sampled(lines, 64), std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(cf_continuous(lines, 64), std::sqrt(2.0), 1e-12);
}

TEST(CfContinuous, SeesThePeakBetweenSamples) {
  // One cosine whose peak falls half-way between samples: the sampled crest factor misses it.
  const std::vector<Line> lines{{1, 1.0, std::numbers::pi / 4.0}};  // period 4: peak at t = −0.5
  EXPECT_LT(cf_sampled(lines, 4), std::sqrt(2.0) - 0.3);
  EXPECT_NEAR(cf_continuous(lines, 4), std::sqrt(2.0), 1e-9);
}

TEST(ValidateLines, RejectsABandBeyondNyquistNamingTheLine) {
  const std::vector<Line> lines{{3, 1.0, 0.0}, {50, 1.0, 0.0}};
  const auto message = message_of([&] { cf_sampled(lines, 100); });
  EXPECT_NE(message.find("lines[1].index = 50"), std::string::npos) << message;
  EXPECT_NE(message.find("Nyquist"), std::string::npos) << message;
}

TEST(ValidateLines, RejectsTooFewLines) {
  const auto message = message_of([] { cf_continuous(std::vector<Line>{}, 100); });
  EXPECT_NE(message.find("too few lines"), std::string::npos) << message;
}

TEST(ValidateLines, RejectsANegativeAmplitudeNamingTheField) {
  const std::vector<Line> lines{{3, -1.0, 0.0}};
  const auto message = message_of([&] { synthesize(lines, 100); });
  EXPECT_NE(message.find("lines[0].amplitude"), std::string::npos) << message;
}

}  // namespace
}  // namespace excite::host::multisine
