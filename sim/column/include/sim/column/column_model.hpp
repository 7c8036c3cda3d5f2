// SPDX-License-Identifier: MIT
#pragma once
// The interface every nonlinear column model implements (SPEC §7, thesis appendix A):
// an autonomous ODE ds/dt = f(s; L, V, F, z_F) in minutes, with the inputs held constant
// over each integration call. ColumnPlant (sim/column/column_plant.hpp) builds the steady
// state, linearisation and simulation on top of it.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "sim/column/operating.hpp"
#include "sim/column/rosenbrock.hpp"

namespace excite::sim::column {

/// Product flows and compositions of a state, for balances and tests.
struct Products {
  double distillate_kmol_min;  ///< D
  double bottoms_kmol_min;     ///< B
  double x_top;                ///< x_D, light-component mole fraction of the distillate
  double x_bottom;             ///< x_B, light-component mole fraction of the bottoms
};

class ColumnModel {
 public:
  virtual ~ColumnModel() = default;

  virtual std::string name() const = 0;
  virtual Eigen::Index state_size() const = 0;
  /// The operating point the model is configured around (nominal L, V, F, z_F).
  virtual Operating nominal() const = 0;
  /// Names of the state components, e.g. "x[3]", "M[3]" (stage numbers as in the README).
  virtual std::vector<std::string> state_names() const = 0;

  /// f(s; op), minutes⁻¹.
  virtual void derivative(const Eigen::VectorXd& s, const Operating& op,
                          Eigen::VectorXd& ds) const = 0;
  /// ∂f/∂s at (s, op), dense.
  virtual Eigen::MatrixXd jacobian(const Eigen::VectorXd& s, const Operating& op) const = 0;

  /// A state from which the steady-state solver converges at op (a rough profile).
  virtual Eigen::VectorXd initial_guess(const Operating& op) const = 0;
  virtual Products products(const Eigen::VectorXd& s, const Operating& op) const = 0;

  /// Throws std::invalid_argument if the state is physically impossible (a holdup at or
  /// below zero, i.e. a stage emptied; a composition far outside [0, 1]).
  virtual void check_state(const Eigen::VectorXd& s) const = 0;

  /// Advances s by duration_min with op held constant. `steps` carries the integrator's
  /// step-size memory between the calls of one trajectory. Throws std::invalid_argument if a stage
  /// empties.
  virtual void integrate(Eigen::VectorXd& s, const Operating& op, double duration_min,
                         StepMemory& steps, const Tolerance& tol,
                         IntegrationStats* stats) const = 0;

  /// Allocates the integrator's buffers now (they are otherwise made on first use), so that
  /// integrate(), products() and check_state() allocate nothing afterwards while they
  /// succeed (an error message allocates).
  virtual void prepare() const = 0;
};

}  // namespace excite::sim::column
