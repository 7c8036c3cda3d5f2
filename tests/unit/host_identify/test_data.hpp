// SPDX-License-Identifier: MIT
#pragma once
// Test data for identification: cut-and-shift PRBS inputs from the firmware signal core
// (SPEC §1) and plant outputs computed by the independent matrix-exponential oracle.

#include <Eigen/Dense>
#include <random>
#include <vector>

#include "firmware/signal/mseq.hpp"
#include "host/identify/element.hpp"
#include "reference_zoh.hpp"

namespace excite::host::testing {

/// Levels uniform in [−1, 1], each held for 7 samples (seeded).
inline Eigen::VectorXd random_levels(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  Eigen::VectorXd u(n);
  double v = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (k % 7 == 0) v = level(rng);
    u(k) = v;
  }
  return u;
}

/// N samples of n simultaneous PRBS (±amplitude), register n_r, each bit held `hold`
/// samples, channel j circularly shifted by j·shift bits.
inline Eigen::MatrixXd prbs_inputs(int n, int n_r, int hold, int shift, Eigen::Index N,
                                   double amplitude) {
  signal::MSequence seq(n_r);
  std::vector<double> bits(seq.period());
  for (auto& b : bits) b = seq.next() ? amplitude : -amplitude;
  Eigen::MatrixXd U(N, n);
  for (int j = 0; j < n; ++j) {
    for (Eigen::Index k = 0; k < N; ++k) {
      const auto bit = static_cast<std::size_t>(k / hold + j * shift) % bits.size();
      U(k, j) = bits[bit];
    }
  }
  return U;
}

/// Y = G U for a p × n matrix of elements (row-major), exact under ZOH, from rest.
inline Eigen::MatrixXd plant_outputs(const std::vector<ElementModel>& G, int p, int n, double T,
                                     const Eigen::MatrixXd& U) {
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(U.rows(), p);
  for (int j = 0; j < p; ++j) {
    for (int i = 0; i < n; ++i) {
      Y.col(j) += reference_response(G[static_cast<std::size_t>(j * n + i)], T, U.col(i));
    }
  }
  return Y;
}

/// Adds white Gaussian noise of the given variance to every entry.
inline void add_noise(Eigen::MatrixXd& Y, double variance, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, std::sqrt(variance));
  for (Eigen::Index c = 0; c < Y.cols(); ++c) {
    for (Eigen::Index r = 0; r < Y.rows(); ++r) Y(r, c) += noise(rng);
  }
}

/// A 4×4 plant with the structure of the column/side-stripper case study (SPEC §7, B.0.5):
/// its gains and delays, each element approximated by two real poles (first-order entries
/// get a small second pole, the lead/complex-pole entry (4,2) two real poles).
inline std::vector<ElementModel> stripper_like_4x4() {
  return {
      {4.09, 1.3, 33.0, 8.3},   {6.36, 1.2, 31.6, 20.0}, {-0.25, 1.4, 21.0, 2.0},
      {-0.49, 6.0, 22.0, 3.0},  {-4.17, 5.0, 45.0, 4.0}, {6.93, 1.02, 44.6, 2.5},
      {-0.05, 6.0, 34.5, 30.0}, {1.53, 3.8, 48.0, 5.0},  {1.73, 18.0, 13.0, 11.0},
      {5.11, 12.0, 13.3, 10.0}, {4.61, 1.01, 18.5, 1.5}, {-5.49, 1.5, 15.0, 2.2},
      {-11.2, 2.6, 43.0, 6.5},  {14.0, 0.02, 45.0, 3.2}, {-0.1, 0.05, 31.6, 5.0},
      {4.49, 0.6, 48.0, 6.3},
  };
}

}  // namespace excite::host::testing
