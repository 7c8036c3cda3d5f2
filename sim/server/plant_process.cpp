// SPDX-License-Identifier: MIT
#include "sim/server/plant_process.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "base/config/error.hpp"

namespace excite::sim::server {
namespace {

std::vector<double> or_plant(const std::vector<double>& values, const Eigen::VectorXd& plant) {
  return values.empty() ? std::vector<double>(plant.data(), plant.data() + plant.size()) : values;
}

}  // namespace

std::unique_ptr<Plant> load_plant(const PlantSettings& settings,
                                  const std::filesystem::path& base_directory,
                                  std::string_view source) {
  if (!settings.file.empty()) {
    std::filesystem::path path(settings.file);
    if (path.is_relative()) path = base_directory / path;
    if (path.extension() != ".toml") {
      throw config::Error(source, {}, "plant.file", "\"" + settings.file + "\"",
                          "a plant file ending in .toml (sim/lti format)");
    }
    return make_plant(path.string());
  }
  if (settings.library.empty()) {
    throw config::Error(source, {}, "plant", "(none)",
                        "plant.library or plant.file in the configuration, or --plant");
  }
  const std::vector<std::string> names = plant_names();
  if (std::find(names.begin(), names.end(), settings.library) == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw config::Error(source, {}, "plant.library", "\"" + settings.library + "\"",
                        "one of " + list + ", or a plant file NAME.toml");
  }
  return make_plant(settings.library);
}

PlantProcess::PlantProcess(std::unique_ptr<Plant> plant, const PlantSettings& settings)
    : plant_(std::move(plant)),
      sample_time_min_(settings.sample_time_min),
      u0_(or_plant(settings.input_baseline, plant_->input_baseline())),
      y0_(or_plant(settings.output_baseline, plant_->output_baseline())),
      du_(static_cast<std::size_t>(plant_->inputs()), 0.0),
      dy_(static_cast<std::size_t>(plant_->outputs()), 0.0) {
  plant_->reset(sample_time_min_);
  if (settings.noise_variance.size() == 1) {
    noise_.emplace(plant_->outputs(), settings.noise_variance.front(), settings.noise_seed);
  } else if (!settings.noise_variance.empty()) {
    noise_.emplace(settings.noise_variance, settings.noise_seed);
  }
}

void PlantProcess::sample(const double* u, double* y) {
  for (std::size_t i = 0; i < du_.size(); ++i) du_[i] = u[i] - u0_[i];
  plant_->step(du_, dy_);
  if (noise_) noise_->add(dy_.data());
  for (std::size_t j = 0; j < dy_.size(); ++j) y[j] = y0_[j] + dy_[j];
  ++k_;
}

}  // namespace excite::sim::server
