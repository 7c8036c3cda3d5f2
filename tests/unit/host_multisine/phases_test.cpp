// SPDX-License-Identifier: MIT
#include "host/multisine/phases.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "host/multisine/synthesis.hpp"
#include "multisine_cases.hpp"

namespace excite::host::multisine {
namespace {

constexpr double kPi = std::numbers::pi;

// Difference of two angles, wrapped to (−π, π].
double angle_difference(double a, double b) {
  return std::remainder(a - b, 2.0 * kPi);
}

using testing::flat_schroeder;

TEST(SchroederEqual, MatchesClosedFormHandValuesForFourLines) {
  // 4.4.8 with N = 4: φ_n = −π n(n−1)/4 → 0, −π/2, −3π/2, −3π.
  const auto phases = schroeder_phases_equal(4);
  ASSERT_EQ(phases.size(), 4U);
  EXPECT_NEAR(angle_difference(phases[0], 0.0), 0.0, 1e-12);
  EXPECT_NEAR(angle_difference(phases[1], -kPi / 2.0), 0.0, 1e-12);
  EXPECT_NEAR(angle_difference(phases[2], -3.0 * kPi / 2.0), 0.0, 1e-12);
  EXPECT_NEAR(angle_difference(phases[3], -3.0 * kPi), 0.0, 1e-12);
}

TEST(SchroederGeneral, MatchesHandValuesForUnequalAmplitudes) {
  // ϑ = {1/4, 1/2, 1/4}: φ_2 = −2π·ϑ_1 = −π/2; φ_3 = −2π(2ϑ_1 + ϑ_2) = −2π.
  const std::vector<double> amplitudes{1.0, std::sqrt(2.0), 1.0};
  const auto phases = schroeder_phases(amplitudes);
  EXPECT_NEAR(angle_difference(phases[0], 0.0), 0.0, 1e-12);
  EXPECT_NEAR(angle_difference(phases[1], -kPi / 2.0), 0.0, 1e-12);
  EXPECT_NEAR(angle_difference(phases[2], -2.0 * kPi), 0.0, 1e-12);
}

TEST(SchroederGeneral, ReducesToTheEqualAmplitudeFormForFlatAmplitudes) {
  const std::vector<double> amplitudes(17, 0.3);
  const auto general = schroeder_phases(amplitudes);
  const auto equal = schroeder_phases_equal(17);
  for (std::size_t k = 0; k < equal.size(); ++k) {
    EXPECT_NEAR(angle_difference(general[k], equal[k]), 0.0, 1e-9) << "line " << k;
  }
}

TEST(SchroederEqual, FlatSpectrumContinuousCrestFactorIsAbout178At31And170At63) {
  EXPECT_NEAR(cf_continuous(flat_schroeder(31), 256), 1.78, 0.01);
  EXPECT_NEAR(cf_continuous(flat_schroeder(63), 256), 1.70, 0.01);
}

TEST(LinearPhases, PutTheWholeAmplitudeSumAtTheDelay) {
  // 4.4.3: φ_i = −τ ω_i makes every cosine peak at t = τ.
  const std::vector<std::uint32_t> indices{1, 2, 3, 5, 8};
  const auto phases = linear_phases(indices, 64, 10.0);
  std::vector<Line> lines;
  for (std::size_t k = 0; k < indices.size(); ++k) lines.push_back({indices[k], 1.0, phases[k]});
  const auto x = synthesize(lines, 64);
  EXPECT_NEAR(x[10], 5.0, 1e-12);
  for (std::size_t t = 0; t < x.size(); ++t) {
    if (t != 10) {
      EXPECT_LT(x[t], 5.0 - 1e-6) << "t = " << t;
    }
  }
}

TEST(RandomPhases, SameSeedGivesTheSameSignal) {
  const auto a = random_phases(40, 1234);
  const auto b = random_phases(40, 1234);
  EXPECT_EQ(a, b);
  std::vector<Line> la;
  std::vector<Line> lb;
  for (std::uint32_t k = 0; k < 40; ++k) {
    la.push_back({k + 1, 1.0, a[k]});
    lb.push_back({k + 1, 1.0, b[k]});
  }
  EXPECT_EQ(synthesize(la, 128), synthesize(lb, 128));
}

TEST(RandomPhases, AreInZeroToTwoPiAndDependOnTheSeed) {
  const auto a = random_phases(1000, 1);
  const auto b = random_phases(1000, 2);
  EXPECT_NE(a, b);
  for (double phase : a) {
    EXPECT_GE(phase, 0.0);
    EXPECT_LT(phase, 2.0 * kPi);
  }
}

TEST(SchroederGeneral, RejectsNoAmplitudesNamingTheField) {
  try {
    schroeder_phases(std::vector<double>{});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("amplitudes"), std::string::npos) << error.what();
  }
}

TEST(SchroederGeneral, RejectsANegativeAmplitudeNamingIt) {
  try {
    schroeder_phases(std::vector<double>{1.0, -0.5});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("amplitudes[1]"), std::string::npos) << error.what();
  }
}

TEST(MakeLines, RejectsAPhaseCountMismatchNamingTheField) {
  const std::vector<std::uint32_t> indices{1, 2, 3};
  const std::vector<double> amplitudes{1.0, 1.0, 1.0};
  const std::vector<double> phases{0.0, 0.0};
  try {
    make_lines(indices, amplitudes, phases);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("phases: 2 values for 3"), std::string::npos)
        << error.what();
  }
}

TEST(MakeLines, RejectsAnAmplitudeCountMismatchNamingTheField) {
  const std::vector<std::uint32_t> indices{1, 2};
  const std::vector<double> amplitudes{1.0};
  const std::vector<double> phases{0.0, 0.0};
  try {
    make_lines(indices, amplitudes, phases);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("amplitudes"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace excite::host::multisine
