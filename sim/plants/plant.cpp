// SPDX-License-Identifier: MIT
#include "sim/plants/plant.hpp"

#include <Eigen/LU>

#include <complex>
#include <stdexcept>

#include "sim/column/column_plant.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/plant_toml.hpp"

namespace excite::sim {
namespace {

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
  Eigen::MatrixXd static_gain() const override { return g_.static_gain(); }
  Eigen::MatrixXcd frequency_response(double omega) const override {
    return g_.frequency_response(omega);
  }
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& du, double sample_time_min) override {
    return DiscretePlant(g_, sample_time_min).simulate(du);
  }

 private:
  std::string name_;
  TransferMatrix g_;
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

 private:
  column::ColumnPlant column_;
};

}  // namespace

std::vector<std::string> plant_names() {
  std::vector<std::string> names = library_plant_names();
  names.emplace_back("colaA");
  names.emplace_back("pilot15");
  return names;
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
