// SPDX-License-Identifier: MIT
#include "sim/server/plant_process.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/library/library.hpp"

namespace excite::sim::server {
namespace {

std::vector<double> or_zeros(const std::vector<double>& values, int n) {
  return values.empty() ? std::vector<double>(static_cast<std::size_t>(n), 0.0) : values;
}

}  // namespace

PlantDefinition load_plant(const PlantSettings& settings,
                           const std::filesystem::path& base_directory, std::string_view source) {
  if (!settings.file.empty()) {
    std::filesystem::path path(settings.file);
    if (path.is_relative()) path = base_directory / path;
    return load_plant_file(path);
  }
  if (settings.library.empty()) {
    throw std::invalid_argument(std::string(source) +
                                ": plant = (none): expected plant.library or plant.file in the "
                                "configuration, or --plant / --plant-file");
  }
  const std::vector<std::string> names = library_plant_names();
  if (std::find(names.begin(), names.end(), settings.library) == names.end()) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw std::invalid_argument(std::string(source) + ": plant.library = \"" + settings.library +
                                "\": expected one of " + list);
  }
  return library_plant_definition(settings.library);
}

PlantProcess::PlantProcess(const TransferMatrix& g, const PlantSettings& settings)
    : plant_(g, settings.sample_time_min),
      u0_(or_zeros(settings.input_baseline, g.inputs())),
      y0_(or_zeros(settings.output_baseline, g.outputs())),
      du_(static_cast<std::size_t>(g.inputs()), 0.0),
      dy_(static_cast<std::size_t>(g.outputs()), 0.0) {
  if (settings.noise_variance.size() == 1) {
    noise_.emplace(g.outputs(), settings.noise_variance.front(), settings.noise_seed);
  } else if (!settings.noise_variance.empty()) {
    noise_.emplace(settings.noise_variance, settings.noise_seed);
  }
}

void PlantProcess::sample(const double* u, double* y) {
  for (std::size_t i = 0; i < du_.size(); ++i) du_[i] = u[i] - u0_[i];
  plant_.step(du_.data(), dy_.data());
  if (noise_) noise_->add(dy_.data());
  for (std::size_t j = 0; j < dy_.size(); ++j) y[j] = y0_[j] + dy_[j];
  ++k_;
}

}  // namespace excite::sim::server
