// SPDX-License-Identifier: MIT
#pragma once
// A coloured output disturbance (issue 41 §3): each output gets v(k), white Gaussian noise
// through a first-order filter of time constant τ (the ZOH discretisation of 1/(τs + 1)),
// v(k+1) = a·v(k) + std·√(1 − a²)·e(k), a = exp(−T/τ), e(k) ~ N(0, 1), so v has the
// stationary standard deviation `std` and the autocorrelation a^|lag|. v(0) = 0: the plant
// starts at rest at its operating point and the disturbance builds up over a few τ. A
// disturbance of the plant's time scale is where naive closed-loop identification goes
// wrong (CLOSED-LOOP.md: the output-error fit on u is biased when the noise is coloured and
// u is correlated with it through the controller).
//
// Deterministic by seed (GaussianSource, noise.hpp: the sequence does not depend on the
// standard library); no allocation after construction.

#include <cstdint>
#include <span>
#include <vector>

#include "sim/lti/noise.hpp"

namespace excite::sim {

class ColouredDisturbance {
 public:
  /// `outputs` channels, each of stationary standard deviation `std_dev` (≥ 0, finite) and
  /// time constant `tau_min` (> 0, finite), sampled every `sample_time_min` (> 0). Throws
  /// std::invalid_argument in the one message form naming the value.
  ColouredDisturbance(int outputs, double std_dev, double tau_min, double sample_time_min,
                      std::uint64_t seed);

  int outputs() const { return static_cast<int>(state_.size()); }
  /// The pole a = exp(−T/τ).
  double pole() const { return pole_; }

  /// Adds v(k) to y (outputs() values), then advances to k + 1.
  void add(std::span<double> y) noexcept;

 private:
  std::vector<double> state_;
  double pole_ = 0.0;
  double drive_ = 0.0;  // std·√(1 − a²)
  GaussianSource source_;
};

/// The seed a disturbance draws from for a run's `seed`: another stream than the
/// measurement noise's, so adding a disturbance leaves the white noise's numbers unchanged.
inline std::uint64_t disturbance_seed(std::uint64_t seed) {
  return seed ^ 0x9E3779B97F4A7C15ULL;
}

}  // namespace excite::sim
