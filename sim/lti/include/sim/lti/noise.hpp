// SPDX-License-Identifier: MIT
#pragma once
// Gaussian measurement noise added to the outputs (thesis 6.3: variance s² = 0.03 on every
// output). Seeded and reproducible: std::mt19937_64 (whose sequence the standard fixes)
// with Box–Muller written here, not std::normal_distribution (whose algorithm differs
// between standard libraries).

#include <Eigen/Dense>
#include <cstdint>
#include <random>
#include <vector>

namespace excite::sim {

/// Standard normal deviates from a seed.
class GaussianSource {
 public:
  explicit GaussianSource(std::uint64_t seed) : engine_(seed) {}
  double next();

 private:
  std::mt19937_64 engine_;
  double spare_ = 0.0;
  bool has_spare_ = false;
};

/// Adds N(0, variance_i) to output i, sample by sample.
class MeasurementNoise {
 public:
  /// One variance per output (in squared output units, ≥ 0 and finite).
  /// Throws std::invalid_argument naming the output and the value.
  MeasurementNoise(std::vector<double> variances, std::uint64_t seed);
  /// The same variance on each of `outputs` outputs.
  MeasurementNoise(int outputs, double variance, std::uint64_t seed);

  int outputs() const { return static_cast<int>(std_dev_.size()); }

  /// Adds one sample of noise to y (outputs() values).
  void add(double* y);
  /// Adds noise to Y (N × outputs()), row by row: the same numbers as N calls of add(row).
  void add(Eigen::MatrixXd& y);

 private:
  std::vector<double> std_dev_;
  GaussianSource source_;
};

}  // namespace excite::sim
