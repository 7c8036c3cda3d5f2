// SPDX-License-Identifier: MIT
#include "sim/plants/plant.hpp"

#include <Eigen/LU>

#include <cmath>
#include <complex>
#include <cstdio>
#include <optional>
#include <stdexcept>

#include "base/config/document.hpp"
#include "sim/column/column_plant.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/plant_toml.hpp"

namespace excite::sim {
namespace {

void require_sample_time(const std::string& plant, double sample_time_min) {
  if (std::isfinite(sample_time_min) && sample_time_min > 0.0) return;
  throw std::invalid_argument(plant +
                              ": sample_time_min = " + config::format_number(sample_time_min) +
                              ", expected a finite number of minutes > 0");
}

// The checks every step() makes before touching the plant (no allocation on success).
void require_step_arguments(const std::string& plant, bool live, std::span<const double> du,
                            std::span<double> dy, int inputs, int outputs) {
  if (!live) {
    throw std::invalid_argument(plant +
                                ": step() before reset(sample_time_min), expected "
                                "reset() to start the live simulation");
  }
  if (du.size() != static_cast<std::size_t>(inputs)) {
    throw std::invalid_argument(plant + ": du has " + std::to_string(du.size()) +
                                " values, expected " + std::to_string(inputs) +
                                " (one deviation per input)");
  }
  if (dy.size() != static_cast<std::size_t>(outputs)) {
    throw std::invalid_argument(plant + ": dy has " + std::to_string(dy.size()) +
                                " values, expected " + std::to_string(outputs) +
                                " (one deviation per output)");
  }
  for (std::size_t j = 0; j < du.size(); ++j) {
    if (!std::isfinite(du[j])) {
      throw std::invalid_argument(plant + ": du[" + std::to_string(j) + "] = " +
                                  config::format_number(du[j]) + ", expected a finite deviation");
    }
  }
}

class LinearPlant final : public Plant {
 public:
  LinearPlant(std::string name, TransferMatrix g) : name_(std::move(name)), g_(std::move(g)) {}

  std::string name() const override { return name_; }
  std::vector<std::string> input_names() const override { return g_.input_names(); }
  std::vector<std::string> output_names() const override { return g_.output_names(); }
  std::vector<std::string> input_units() const override {
    return std::vector<std::string>(static_cast<std::size_t>(g_.inputs()), "-");
  }
  std::vector<std::string> output_units() const override {
    return std::vector<std::string>(static_cast<std::size_t>(g_.outputs()), "-");
  }
  Eigen::VectorXd input_baseline() const override { return Eigen::VectorXd::Zero(g_.inputs()); }
  Eigen::VectorXd output_baseline() const override { return Eigen::VectorXd::Zero(g_.outputs()); }
  Eigen::MatrixXd static_gain() const override { return g_.static_gain(); }
  Eigen::MatrixXcd frequency_response(double omega) const override {
    return g_.frequency_response(omega);
  }
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& du, double sample_time_min) override {
    return DiscretePlant(g_, sample_time_min).simulate(du);
  }
  void reset(double sample_time_min) override {
    require_sample_time(name_, sample_time_min);
    if (live_ && live_->sample_time_min() == sample_time_min) {
      live_->reset();
    } else {
      live_.reset();
      live_.emplace(g_, sample_time_min);
    }
  }
  void step(std::span<const double> du, std::span<double> dy) override {
    require_step_arguments(name_, live_.has_value(), du, dy, g_.inputs(), g_.outputs());
    live_->step(du.data(), dy.data());
  }

 private:
  std::string name_;
  TransferMatrix g_;
  std::optional<DiscretePlant> live_;  // the live simulation, from reset() on
};

class Column final : public Plant {
 public:
  explicit Column(column::ColumnPlant column) : column_(std::move(column)) {}

  std::string name() const override { return column_.name(); }
  std::vector<std::string> input_names() const override { return column_.input_names(); }
  std::vector<std::string> output_names() const override { return column_.output_names(); }
  std::vector<std::string> input_units() const override { return {"kmol/min", "kmol/min"}; }
  std::vector<std::string> output_units() const override { return {"mol/mol", "mol/mol"}; }
  Eigen::VectorXd input_baseline() const override {
    const column::Operating op = column_.nominal_operating();
    return Eigen::Vector2d(op.reflux_kmol_min, op.boilup_kmol_min);
  }
  Eigen::VectorXd output_baseline() const override { return column_.nominal_outputs(); }
  Eigen::MatrixXd static_gain() const override { return column_.static_gain(); }
  Eigen::MatrixXcd frequency_response(double omega) const override {
    const auto& lin = column_.linearise();
    const Eigen::Index n = lin.a.rows();
    const Eigen::MatrixXcd resolvent =
        (std::complex<double>(0.0, omega) * Eigen::MatrixXcd::Identity(n, n) -
         lin.a.cast<std::complex<double>>())
            .partialPivLu()
            .solve(lin.b.cast<std::complex<double>>());
    return lin.c.cast<std::complex<double>>() * resolvent;
  }
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& du, double sample_time_min) override {
    column_.reset();
    return column_.simulate(du, sample_time_min);
  }
  // The live simulation runs on its own copy of the column (built at the first reset()), so
  // simulate() leaves it alone.
  void reset(double sample_time_min) override {
    require_sample_time(column_.name(), sample_time_min);
    if (!live_) live_.emplace(column::ColumnPlant::by_name(column_.name()));
    live_->reset();
    live_->set_sample_time_min(sample_time_min);
  }
  void step(std::span<const double> du, std::span<double> dy) override {
    require_step_arguments(column_.name(), live_.has_value(), du, dy, 2, 2);
    live_->step(du.data(), dy.data());
  }

 private:
  column::ColumnPlant column_;
  std::optional<column::ColumnPlant> live_;
};

}  // namespace

std::vector<std::string> plant_names() {
  std::vector<std::string> names = library_plant_names();
  names.emplace_back("colaA");
  names.emplace_back("pilot15");
  return names;
}

std::unique_ptr<Plant> make_linear_plant(std::string name, TransferMatrix g) {
  return std::make_unique<LinearPlant>(std::move(name), std::move(g));
}

std::unique_ptr<Plant> make_plant(std::string_view name_or_path) {
  if (name_or_path.ends_with(".toml")) {
    const PlantDefinition definition = load_plant_file(std::string(name_or_path));
    return std::make_unique<LinearPlant>(
        definition.name.empty() ? std::string(name_or_path) : definition.name, definition.g);
  }
  if (name_or_path == "colaA") return std::make_unique<Column>(column::ColumnPlant::cola_a());
  if (name_or_path == "pilot15") return std::make_unique<Column>(column::ColumnPlant::pilot15());
  for (const std::string& name : library_plant_names()) {
    if (name == name_or_path) return std::make_unique<LinearPlant>(name, library_plant(name));
  }
  std::string known;
  for (const std::string& name : plant_names()) known += (known.empty() ? "" : ", ") + name;
  throw std::invalid_argument("plant = \"" + std::string(name_or_path) +
                              "\", expected one of: " + known + ", or a plant file NAME.toml");
}

}  // namespace excite::sim
