// SPDX-License-Identifier: MIT
#pragma once
// The simulated process behind the registers: a DiscretePlant in deviation variables around
// an operating point, with seeded measurement noise (sim/lti). One call of sample() is one
// plant sample k: u(k) absolute → du(k) = u(k) − u0 → DiscretePlant::step → dy(k) + noise →
// y(k) = y0 + dy(k).

#include <cstdint>
#include <optional>
#include <vector>

#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/noise.hpp"
#include "sim/lti/plant_toml.hpp"
#include "sim/lti/transfer_matrix.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {

/// The plant named by the settings: a library plant (sim/library) or a plant file, a
/// relative path taken from `base_directory`. Throws std::invalid_argument
/// "<source>: plant.library = ...: expected ..." (or the plant file's own error).
PlantDefinition load_plant(const PlantSettings& settings,
                           const std::filesystem::path& base_directory,
                           std::string_view source = "config");

class PlantProcess {
 public:
  /// Baselines and noise from `settings` (sizes already checked by compile_layout; empty
  /// baselines are zeros). Throws std::invalid_argument for a bad sample time.
  PlantProcess(const TransferMatrix& g, const PlantSettings& settings);

  int inputs() const { return plant_.inputs(); }
  int outputs() const { return plant_.outputs(); }
  double sample_time_min() const { return plant_.sample_time_min(); }
  const std::vector<double>& input_baseline() const { return u0_; }
  const std::vector<double>& output_baseline() const { return y0_; }

  /// Sample k: reads u(k) (absolute, inputs() values), writes y(k) (absolute, outputs()
  /// values), advances k. Allocation-free.
  void sample(const double* u, double* y);

  /// Samples taken so far (the k of the next sample).
  std::uint64_t samples() const { return k_; }
  /// The last sample's deviations (for the run log).
  const std::vector<double>& last_du() const { return du_; }
  const std::vector<double>& last_dy() const { return dy_; }

 private:
  DiscretePlant plant_;
  std::vector<double> u0_;
  std::vector<double> y0_;
  std::optional<MeasurementNoise> noise_;
  std::vector<double> du_;
  std::vector<double> dy_;
  std::uint64_t k_ = 0;
};

}  // namespace excite::sim::server
