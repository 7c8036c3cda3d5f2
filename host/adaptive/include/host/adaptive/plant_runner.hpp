// SPDX-License-Identifier: MIT
#pragma once
// The adaptive test on a simulated plant, in-process: each segment's table stepped through
// the plant's live simulation (sim/plants/plant.hpp: reset once, then one step per row, so
// segment k + 1 starts from the state segment k left), measurement noise added per output
// (sim::MeasurementNoise, one stream from the seed for the whole test). The noise-free
// outputs are kept as dy_true (CV limit violations are judged on them).

#include <cstdint>

#include "host/adaptive/adaptive_test.hpp"
#include "sim/lti/noise.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

class PlantRunner final : public SegmentRunner {
 public:
  /// `plant` must outlive the runner; it is reset to rest at `sample_time_min`.
  /// Throws std::invalid_argument for a negative or non-finite noise variance.
  PlantRunner(sim::Plant& plant, double sample_time_min, double noise_variance, std::uint64_t seed);

  /// Throws std::invalid_argument when the segment's channels are not the plant's inputs or
  /// its sample time is not the runner's.
  MeasuredSegment run(const plan::Plan& segment) override;

 private:
  sim::Plant& plant_;
  double sample_time_min_;
  sim::MeasurementNoise noise_;
};

}  // namespace excite::host
