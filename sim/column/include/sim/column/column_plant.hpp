// SPDX-License-Identifier: MIT
#pragma once
// A nonlinear column as a 2×2 plant (SPEC §7): inputs are the deviations of reflux L and
// boil-up V from their nominal values (kmol/min), outputs the deviations of the top and
// bottom compositions x_D, x_B (mole fractions) from their nominal steady state. Time in
// minutes. Feed rate F and composition z_F are disturbances, settable at any time.
//
// Lifecycle: construction solves the nominal steady state and puts the plant there;
// simulate() and step() advance it; reset() returns it to the nominal steady state.
// Not thread-safe (one plant per thread).

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

#include "sim/column/column_model.hpp"

namespace excite::sim::column {

/// The linearisation ds/dt = A ds + B du, dy = C ds about a steady state.
struct Linearisation {
  Eigen::MatrixXd a;  ///< ∂f/∂s, 1/min
  Eigen::MatrixXd b;  ///< ∂f/∂(L, V), central differences
  Eigen::MatrixXd c;  ///< selects (x_D, x_B)
  Eigen::VectorXcd eigenvalues() const { return a.eigenvalues(); }
  /// −C A⁻¹ B: the steady-state gain from (L, V) to (x_D, x_B), mole fraction per kmol/min.
  Eigen::MatrixXd static_gain() const;
};

class ColumnPlant {
 public:
  explicit ColumnPlant(std::unique_ptr<ColumnModel> model);

  /// The benchmark column A (sim/column/cola_a.hpp).
  static ColumnPlant cola_a();
  /// The 15-tray ethanol–water pilot column (sim/column/pilot15.hpp).
  static ColumnPlant pilot15();
  /// By name: "colaA" or "pilot15"; throws std::invalid_argument naming the known plants.
  static ColumnPlant by_name(const std::string& name);

  std::string name() const { return model_->name(); }
  int inputs() const { return 2; }
  int outputs() const { return 2; }
  std::vector<std::string> input_names() const { return {"L", "V"}; }
  std::vector<std::string> output_names() const { return {"xD", "xB"}; }

  /// Steady-state gain d(x_D, x_B)/d(L, V) at the nominal point, −C A⁻¹ B of linearise().
  Eigen::MatrixXd static_gain() const { return nominal_linearisation_.static_gain(); }
  /// Linearisation at the nominal steady state.
  const Linearisation& linearise() const { return nominal_linearisation_; }
  /// Linearisation at any state and operating point.
  Linearisation linearise(const Eigen::VectorXd& state, const Operating& op) const;

  /// Steady state at op (Newton, sim/column/steady_state.hpp), starting from the nominal.
  Eigen::VectorXd steady_state(const Operating& op) const;
  const Eigen::VectorXd& nominal_state() const { return nominal_state_; }
  Operating nominal_operating() const { return model_->nominal(); }
  /// Nominal steady-state (x_D, x_B).
  Eigen::Vector2d nominal_outputs() const { return nominal_y_; }
  const ColumnModel& model() const { return *model_; }

  /// Feed disturbances (absolute values: kmol/min, mole fraction); they act from the next
  /// simulate()/step() on. Throws std::invalid_argument for a non-finite or negative F or
  /// z_F outside [0, 1].
  void set_disturbances(double feed_kmol_min, double feed_light);

  /// The cap on the integrator's attempted steps (accepted + rejected) in one sample of
  /// simulate() or step(); a sample that needs more throws std::runtime_error and is not
  /// committed. Default kDefaultMaxStepsPerSample. n ≥ 1, else std::invalid_argument.
  static constexpr long kDefaultMaxStepsPerSample = 500;
  void set_max_steps_per_sample(long n);
  long max_steps_per_sample() const { return tol_.max_steps; }

  /// U: N × 2 deviations of (L, V) from nominal, each held for sample_time_min (ZOH).
  /// Returns Y: N × 2 deviations of (x_D, x_B) from nominal, row k sampled at the start of
  /// interval k (before U row k acts). Continues from the current state and leaves the
  /// plant at the end of the run. Throws std::invalid_argument for non-finite inputs,
  /// absolute flows below zero, or inputs that drain a stage, and std::runtime_error for a
  /// sample beyond max_steps_per_sample() (the state is then the one at the start of the
  /// failing interval).
  Eigen::MatrixXd simulate(const Eigen::MatrixXd& U, double sample_time_min);

  /// One sample for a plant server: y ← current output deviations (x_D, x_B), then u (the
  /// (L, V) deviations) is held for sample_time_min(). Same errors as simulate().
  /// Bounded work: one integration call of at most max_steps_per_sample() attempted steps
  /// (README.md, "Live stepping"). Allocates nothing after reset() unless it throws.
  void step(const double* u, double* y);
  void set_sample_time_min(double t);
  double sample_time_min() const { return sample_time_min_; }

  /// Back to the nominal steady state (and nominal disturbances); makes the integrator's
  /// buffers, so that step() allocates nothing afterwards.
  void reset();
  const Eigen::VectorXd& state() const { return state_; }
  /// Sets the state (e.g. a steady state from steady_state()); checked by the model.
  void set_state(const Eigen::VectorXd& s);

  /// Integrator tolerances (default 1e-7 absolute and relative, max_steps
  /// kDefaultMaxStepsPerSample; see README.md). tol.max_steps = 0 lifts the cap.
  void set_tolerance(const Tolerance& tol) { tol_ = tol; }
  const IntegrationStats& stats() const { return stats_; }

 private:
  Eigen::Vector2d output_deviation() const;
  void advance(const double* u, double duration_min, long sample);

  std::unique_ptr<ColumnModel> model_;
  Eigen::VectorXd nominal_state_;
  Eigen::Vector2d nominal_y_;
  Linearisation nominal_linearisation_;
  Eigen::VectorXd state_;
  Operating disturbance_;      // F and z_F used by the next interval
  StepMemory steps_{};         // integrator's step-size memory, carried between intervals
  Eigen::VectorXd trial_;      // the interval being integrated, committed when it completes
  std::string input_context_;  // "<name> inputs (nominal + deviation)", for errors
  double sample_time_min_ = 1.0;
  // colaA: compositions within ≈ 5e-9 of a 1e-12 run (bench).
  Tolerance tol_{1e-7, 1e-7, kDefaultMaxStepsPerSample};
  IntegrationStats stats_{};
  long samples_ = 0;  // samples stepped since reset(), for error messages
};

}  // namespace excite::sim::column
