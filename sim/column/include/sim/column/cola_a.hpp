// SPDX-License-Identifier: MIT
#pragma once
// "Column A", the literature's distillation benchmark (Skogestad & Morari; Skogestad's
// cola model), in the LV configuration: reflux L and boil-up V manipulated, condenser and
// reboiler holdups on proportional level loops D = D₀ + K(M_D − M₀), B = B₀ + K(M_B − M₀).
// Binary, constant relative volatility, constant molar flows, linearised liquid dynamics
// L_i = L₀_i + (M_i − M₀)/τ_L + λ(V_{i−1} − V₀) (the simplified appendix A: A.1.1, A.1.3,
// A.1.4 with E = 1, condenser A.1.6–A.1.7).
//
// Stages are numbered 1…N from the bottom: 1 is the reboiler, N the total condenser.
// State s = (x_1, M_1, x_2, M_2, …, x_N, M_N): liquid mole fraction of the light component
// and holdup in kmol. Time in minutes.

#include <memory>

#include "sim/column/column_model.hpp"

namespace excite::sim::column {

struct ColaAParameters {
  int stages = 41;      ///< N, counting reboiler (1) and total condenser (N)
  int feed_stage = 21;  ///< from the bottom
  double relative_volatility = 1.5;
  double feed_liquid_fraction = 1.0;        ///< q_F: 1 = saturated liquid feed
  double holdup_kmol = 0.5;                 ///< M₀, every stage's nominal holdup
  double liquid_time_constant_min = 0.063;  ///< τ_L
  double vapour_liquid_coupling = 0.0;      ///< λ
  double level_gain_per_min = 10.0;         ///< K of both level loops, kmol/min per kmol
  double distillate_bias_kmol_min = 0.5;    ///< D₀
  double bottoms_bias_kmol_min = 0.5;       ///< B₀
  Operating nominal{2.70629, 3.20629, 1.0, 0.5};
};

class ColaA final : public ColumnModel {
 public:
  explicit ColaA(ColaAParameters p = {});
  ~ColaA() override;

  std::string name() const override { return "colaA"; }
  Eigen::Index state_size() const override { return 2 * stages_; }
  Operating nominal() const override { return p_.nominal; }
  std::vector<std::string> state_names() const override;
  void derivative(const Eigen::VectorXd& s, const Operating& op,
                  Eigen::VectorXd& ds) const override;
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& s, const Operating& op) const override;
  Eigen::VectorXd initial_guess(const Operating& op) const override;
  Products products(const Eigen::VectorXd& s, const Operating& op) const override;
  void check_state(const Eigen::VectorXd& s) const override;
  void integrate(Eigen::VectorXd& s, const Operating& op, double duration_min, StepMemory& steps,
                 const Tolerance& tol, IntegrationStats* stats) const override;
  void prepare() const override;

  const ColaAParameters& parameters() const { return p_; }

  /// The ODE at a fixed operating point, in the form the integrator wants.
  class System;

 private:
  struct Workspace;
  ColaAParameters p_;
  Eigen::Index stages_;
  mutable std::unique_ptr<Workspace> work_;  // integrator buffers, reused between calls
};

}  // namespace excite::sim::column
