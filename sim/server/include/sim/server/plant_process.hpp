// SPDX-License-Identifier: MIT
#pragma once
// The simulated process behind the registers: any sim::Plant (linear library plants, plant
// files, the nonlinear columns colaA and pilot15) stepped live, one sample per call, in
// deviation variables around an operating point, with seeded measurement noise (sim/lti).
// One call of sample() is one plant sample k: u(k) absolute → du(k) = u(k) − u0 →
// Plant::step → dy(k) + noise → y(k) = y0 + dy(k).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "sim/lti/noise.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/server_config.hpp"

namespace excite::sim::server {

/// The plant named by the settings: a plant `make_plant` knows (sim/plants: the library
/// plants, colaA, pilot15) or a plant file (sim/lti format, ending in .toml), a relative
/// path taken from `base_directory`. Throws std::invalid_argument
/// "<source>: plant.library = ..., expected ..." (or the plant file's own error).
std::unique_ptr<Plant> load_plant(const PlantSettings& settings,
                                  const std::filesystem::path& base_directory,
                                  std::string_view source = "config");

class PlantProcess {
 public:
  /// Resets the plant at settings.sample_time_min. Operating point: settings' baselines,
  /// or, when empty, the plant's own (input_baseline(), output_baseline(): zeros for the
  /// linear plants, the columns' nominal flows and compositions). Noise from the settings
  /// (sizes already checked by compile_layout). Throws std::invalid_argument for a bad
  /// sample time.
  PlantProcess(std::unique_ptr<Plant> plant, const PlantSettings& settings);

  int inputs() const { return static_cast<int>(du_.size()); }
  int outputs() const { return static_cast<int>(dy_.size()); }
  double sample_time_min() const { return sample_time_min_; }
  const std::vector<double>& input_baseline() const { return u0_; }
  const std::vector<double>& output_baseline() const { return y0_; }
  const Plant& plant() const { return *plant_; }

  /// Sample k: reads u(k) (absolute, inputs() values), writes y(k) (absolute, outputs()
  /// values), advances k. No allocation (the plant's step allocates nothing after reset).
  void sample(const double* u, double* y);

  /// Samples taken so far (the k of the next sample).
  std::uint64_t samples() const { return k_; }
  /// The last sample's deviations (for the run log).
  const std::vector<double>& last_du() const { return du_; }
  const std::vector<double>& last_dy() const { return dy_; }

 private:
  std::unique_ptr<Plant> plant_;
  double sample_time_min_;
  std::vector<double> u0_;
  std::vector<double> y0_;
  std::optional<MeasurementNoise> noise_;
  std::vector<double> du_;
  std::vector<double> dy_;
  std::uint64_t k_ = 0;
};

}  // namespace excite::sim::server
