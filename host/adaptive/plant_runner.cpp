// SPDX-License-Identifier: MIT
#include "host/adaptive/plant_runner.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "host/design/table.hpp"

namespace excite::host {

PlantRunner::PlantRunner(sim::Plant& plant, double sample_time_min, double noise_variance,
                         std::uint64_t seed)
    : plant_(plant),
      sample_time_min_(sample_time_min),
      noise_(plant.outputs(), noise_variance, seed) {
  plant_.reset(sample_time_min);
}

MeasuredSegment PlantRunner::run(const plan::Plan& segment) {
  if (static_cast<int>(segment.recipe.channels) != plant_.inputs()) {
    throw std::invalid_argument("segment channels = " + std::to_string(segment.recipe.channels) +
                                ", expected " + std::to_string(plant_.inputs()) +
                                " (the plant's inputs)");
  }
  if (std::abs(segment.meta.sample_time_min - sample_time_min_) > 1e-9 * sample_time_min_) {
    throw std::invalid_argument(
        "segment sample time = " + std::to_string(segment.meta.sample_time_min) +
        " min, expected " + std::to_string(sample_time_min_) + " min");
  }
  const Table table = make_table(segment.recipe);
  MeasuredSegment m;
  m.du = table;
  m.dy_true.resize(table.rows(), plant_.outputs());
  Eigen::VectorXd du(plant_.inputs()), dy(plant_.outputs());
  for (Eigen::Index k = 0; k < table.rows(); ++k) {
    du = table.row(k).transpose();
    plant_.step(std::span<const double>(du.data(), static_cast<std::size_t>(du.size())),
                std::span<double>(dy.data(), static_cast<std::size_t>(dy.size())));
    m.dy_true.row(k) = dy.transpose();
  }
  m.dy = m.dy_true;
  noise_.add(m.dy);
  return m;
}

}  // namespace excite::host
