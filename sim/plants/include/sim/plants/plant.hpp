// SPDX-License-Identifier: MIT
#pragma once
// Every plant the tools can simulate, behind one interface: the linear library plants and
// TOML plant files (sim/lti, sim/library) and the nonlinear columns (sim/column). Inputs
// and outputs are deviations from the operating point; time in minutes.
//
// Two ways to run a plant, independent of each other:
//   batch  simulate(du, T): a whole experiment from rest;
//   live   reset(T), then step(du(k), dy(k)) once per sample (a plant server, an in-process
//          link): the same trajectory one sample at a time, with bounded work and no
//          allocation per step. simulate() does not disturb the live state.
// A column's step() may also refuse a sample its inputs make impossible (a stage drained:
// std::invalid_argument) or one over its work cap (std::runtime_error,
// sim/column/README.md "Live stepping"); the refused sample is not taken.

#include <Eigen/Core>

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "sim/lti/transfer_matrix.hpp"

namespace excite::sim {

class Plant {
 public:
  virtual ~Plant() = default;

  virtual std::string name() const = 0;
  virtual std::vector<std::string> input_names() const = 0;
  virtual std::vector<std::string> output_names() const = 0;
  /// Engineering units, one token each ("-" when dimensionless or unknown).
  virtual std::vector<std::string> input_units() const = 0;
  virtual std::vector<std::string> output_units() const = 0;
  /// Absolute inputs at the operating point (0 for the linear models).
  virtual Eigen::VectorXd input_baseline() const = 0;
  /// Absolute outputs at the operating point (0 for the linear models).
  virtual Eigen::VectorXd output_baseline() const = 0;
  /// Steady-state gain G(0), outputs × inputs (the columns: linearised at the nominal point).
  virtual Eigen::MatrixXd static_gain() const = 0;
  /// Open-loop response from rest at the operating point to input deviations `du`
  /// (N × inputs, held over each sample), sampled at the start of each interval: N × outputs.
  /// Throws std::invalid_argument on a wrong column count or non-finite inputs.
  virtual Eigen::MatrixXd simulate(const Eigen::MatrixXd& du, double sample_time_min) = 0;

  /// Live simulation: puts the plant at rest at its operating point, sampled every
  /// sample_time_min minutes. Throws std::invalid_argument for a non-finite or non-positive T.
  virtual void reset(double sample_time_min) = 0;
  /// One sample k: writes dy(k) (output deviations sampled at kT, before du(k) acts — the
  /// convention of simulate()), then holds du(k) (input deviations) over [kT, (k+1)T) and
  /// advances k. Bounded work per call; no allocation after reset(). Throws
  /// std::invalid_argument on wrong sizes or non-finite du, or if reset() was not called.
  virtual void step(std::span<const double> du, std::span<double> dy) = 0;

  /// G(jω), outputs × inputs, ω in rad/min (the columns: their linearisation at the
  /// nominal point, C (jωI − A)⁻¹ B).
  virtual Eigen::MatrixXcd frequency_response(double omega_rad_per_min) const = 0;

  int inputs() const { return static_cast<int>(input_names().size()); }
  int outputs() const { return static_cast<int>(output_names().size()); }
};

/// Names `make_plant` knows: the linear library plants, then colaA and pilot15.
std::vector<std::string> plant_names();

/// A linear plant from its transfer-function matrix (minutes), named `name`.
std::unique_ptr<Plant> make_linear_plant(std::string name, TransferMatrix g);

/// A plant by name, or from a TOML plant file when `name_or_path` ends in ".toml"
/// (sim/lti/README.md). std::invalid_argument listing the known names otherwise.
std::unique_ptr<Plant> make_plant(std::string_view name_or_path);

}  // namespace excite::sim
