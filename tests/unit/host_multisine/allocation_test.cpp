// SPDX-License-Identifier: MIT
#include "host/multisine/allocation.hpp"

#include <gtest/gtest.h>

#include <complex>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/FFT>

#include "host/multisine/synthesis.hpp"
#include "multisine_cases.hpp"

namespace excite::host::multisine {
namespace {

using testing::case_study_gain;

// One period's DFT of channel c (bins 0 … P/2).
std::vector<std::complex<double>> spectrum_of(const MultisineSet& set, std::size_t c) {
  const auto x = synthesize(channel_spectrum(set, c), set.period);
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> bins;
  fft.fwd(bins, x);
  return bins;
}

TEST(ZipperedSet, PutsChannelJOnLinesNDeltaPlusJStepN) {
  const auto set = zippered_set(200, {4, 2, 5, 1, 1.0});
  for (std::uint32_t c = 0; c < 4; ++c) {
    ASSERT_EQ(set.channels[c].size(), 5U);
    for (std::uint32_t k = 0; k < 5; ++k) {
      EXPECT_EQ(set.channels[c][k].index, 4 * (2 + k) + c + 1);  // 4.4.18
    }
    // Snow: j, n + j (4.4.19, δ = 2) and n(δ + n_s) + j (4.4.20, n_a = 1).
    EXPECT_EQ(set.snow[c], (std::vector<std::uint32_t>{c + 1, 4 + c + 1, 4 * 7 + c + 1}));
  }
}

TEST(ZipperedSet, ChannelsHaveZeroCrossSpectrumOnEveryLine) {
  const auto set = zippered_set(256, {4, 1, 12, 0, 1.0});
  std::vector<std::vector<std::complex<double>>> spectra;
  for (std::size_t c = 0; c < 4; ++c) spectra.push_back(spectrum_of(set, c));
  for (std::size_t a = 0; a < 4; ++a) {
    for (std::size_t b = a + 1; b < 4; ++b) {
      for (std::size_t i = 1; i < 128; ++i) {
        EXPECT_NEAR(std::abs(spectra[a][i] * std::conj(spectra[b][i])), 0.0, 1e-9)
            << "channels " << a << ", " << b << " line " << i;
      }
    }
  }
}

TEST(ZipperedSet, ChannelsAreUncorrelatedAtLagZeroOverAPeriod) {
  const auto set = zippered_set(256, {4, 0, 12, 0, 1.0});
  std::vector<std::vector<double>> x;
  for (std::size_t c = 0; c < 4; ++c) x.push_back(synthesize(channel_spectrum(set, c), 256));
  for (std::size_t a = 0; a < 4; ++a) {
    for (std::size_t b = a + 1; b < 4; ++b) {
      double cross = 0.0;
      for (std::size_t t = 0; t < 256; ++t) cross += x[a][t] * x[b][t];
      EXPECT_NEAR(cross / 256.0, 0.0, 1e-12) << "channels " << a << ", " << b;
    }
  }
}

TEST(ModifiedZipperedSet, FollowsTheLineLayoutOf4421) {
  const auto set = modified_zippered_set(400, {4, 1, 6, 0, 1.0}, case_study_gain(), {});
  ASSERT_EQ(set.shared.size(), 1U);
  for (std::uint32_t k = 0; k < 6; ++k) {
    for (std::uint32_t c = 0; c < 4; ++c) {
      EXPECT_EQ(set.channels[c][k].index, 5 * (1 + k) + c + 1);  // (n+1)(δ+k) + j
    }
    EXPECT_EQ(set.shared[0].lines[k].index, 5 * (1 + k + 1));  // (n+1)(δ+k+1)
  }
}

TEST(ModifiedZipperedSet, SharedLinesCarryInputVectorsParallelToTheWeakestDirection) {
  const Eigen::MatrixXd gain = case_study_gain();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(gain, Eigen::ComputeFullV);
  ASSERT_NEAR(svd.singularValues()(3), 0.1635, 5e-4);
  const Eigen::VectorXd v_n = svd.matrixV().col(3);
  const auto set = modified_zippered_set(400, {4, 0, 8, 0, 1.0}, gain, {});
  std::vector<std::vector<std::complex<double>>> spectra;
  for (std::size_t c = 0; c < 4; ++c) spectra.push_back(spectrum_of(set, c));
  for (const Line& line : set.shared[0].lines) {
    // The input vector at this line, (U_1(i) … U_4(i)), must be a complex multiple of v_n.
    Eigen::VectorXcd u(4);
    for (Eigen::Index c = 0; c < 4; ++c) u(c) = spectra[static_cast<std::size_t>(c)][line.index];
    const double alignment = std::abs(v_n.cast<std::complex<double>>().dot(u)) / u.norm();
    EXPECT_NEAR(alignment, 1.0, 1e-12) << "line " << line.index;
  }
}

TEST(ModifiedZipperedSet, AThresholdOnXiAddsEveryWeakDirection) {
  // ξ = σ_1/σ_i = 1, 2.02, 4.06, 125.2: a threshold of 3 adds v_3 to v_4.
  ModifiedZipperedOptions options;
  options.xi_threshold = 3.0;
  const auto set = modified_zippered_set(600, {4, 0, 6, 0, 1.0}, case_study_gain(), options);
  ASSERT_EQ(set.shared.size(), 2U);
  EXPECT_EQ(set.shared[0].lines[0].index, 5U);  // slots of 6: channels 1–4, v_4 at 5, v_3 at 6
  EXPECT_EQ(set.shared[1].lines[0].index, 6U);
  Eigen::Map<const Eigen::VectorXd> first(set.shared[0].direction.data(), 4);
  Eigen::Map<const Eigen::VectorXd> second(set.shared[1].direction.data(), 4);
  EXPECT_NEAR(first.dot(second), 0.0, 1e-12);
}

TEST(ModifiedZipperedSet, RejectsAGainOfTheWrongSizeNamingIt) {
  try {
    modified_zippered_set(400, {3, 0, 6, 0, 1.0}, case_study_gain(), {});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("gain"), std::string::npos) << error.what();
  }
}

TEST(StandardSet, PutsEveryChannelOnTheSameLines) {
  const auto set = standard_set(3, 100, 2, 10, 0.5);
  ASSERT_EQ(set.channels.size(), 3U);
  for (const auto& lines : set.channels) {
    ASSERT_EQ(lines.size(), 10U);
    for (std::uint32_t k = 0; k < 10; ++k) {
      EXPECT_EQ(lines[k].index, 2 + k);
      EXPECT_EQ(lines[k].amplitude, 0.5);
    }
  }
}

TEST(WeakInputDirections, AreUnitVectorsWithTheirLargestEntryPositive) {
  const auto directions = weak_input_directions(case_study_gain(), 0.0);
  ASSERT_EQ(directions.size(), 1U);
  EXPECT_NEAR(directions[0].norm(), 1.0, 1e-12);
  Eigen::Index largest = 0;
  directions[0].cwiseAbs().maxCoeff(&largest);
  EXPECT_GT(directions[0](largest), 0.0);
  // v_n is the input the plant barely amplifies: ‖G v_n‖ = σ_n = 0.1635.
  EXPECT_NEAR((case_study_gain() * directions[0]).norm(), 0.1635, 5e-4);
}

TEST(ZipperedSet, RejectsABandBeyondNyquist) {
  try {
    zippered_set(100, {4, 0, 13, 0, 1.0});  // top line 52 ≥ 50
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("Nyquist"), std::string::npos) << error.what();
  }
}

TEST(ZipperedSet, RejectsTooFewLines) {
  try {
    zippered_set(100, {4, 0, 0, 0, 1.0});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("too few lines"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace excite::host::multisine
