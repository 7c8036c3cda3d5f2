// SPDX-License-Identifier: MIT
#pragma once
// A 15-tray ethanol–water pilot column like the reference thesis's (appendix A; SPEC §7),
// with the slips of SPEC §8 corrected. Trays are numbered 1…N = 15 from the top; stage 0 is
// the total condenser with its reflux drum, then the thermosyphon reboiler with its
// compartment, and the bottom sump.
//  - trays: A.1.1, A.1.3; Murphree efficiency A.1.4 with y*(x) from sim/column/ethanol_water;
//    liquid outflow by the Francis weir (A.1.2), with the composition-dependent molar
//    volume; constant molar overflow (A.1.5 with equal molar heats, no heat loss), so
//    every tray sees the reboiler's vapour V_{N+1}.
//  - condenser: A.1.6–A.1.7 (total, saturated reflux; the energy balance A.1.8–A.1.9 of a
//    subcooling condenser is not modelled). D on a proportional level loop of the drum.
//  - reboiler: A.1.10–A.1.20 with R = L_{N+1}/L_r and L_r = V_{N+1}/(1 − R) (SPEC §8);
//    heat input τ_r dQ_r/dt = h_V V − Q_r, V_{N+1} = Q_r/h_V (A.1.15–A.1.16) is carried as
//    τ_r dV_{N+1}/dt = V − V_{N+1} (the same equation divided by the constant h_V). B on a
//    proportional level loop of the sump.
// State: (x_0, M_0, x_1, M_1, …, x_N, M_N, x_r, V_{N+1}, M_B, m_B); x as light (ethanol)
// mole fractions, M in kmol, V_{N+1} in kmol/min, m_B = M_B x_B in kmol. Time in minutes.

#include <memory>

#include "sim/column/column_model.hpp"
#include "sim/column/ethanol_water.hpp"

namespace excite::sim::column {

struct Pilot15Parameters {
  int trays = 15;
  int feed_tray = 10;                 ///< from the top
  double murphree_efficiency = 0.65;  ///< E_i of every tray
  double reboiler_efficiency = 0.9;   ///< E_r (A.1.19)
  double tray_area_m2 = 0.0177;       ///< active area, 0.15 m diameter
  double weir_height_m = 0.025;
  double weir_length_m = 0.10;
  double francis_coefficient = 1.84;             ///< Q = c·l_w·h_ow^1.5, m³/s with metres
  double ethanol_molar_volume_m3_kmol = 0.0585;  ///< 46.07 kg/kmol / 787 kg/m³
  double water_molar_volume_m3_kmol = 0.0181;    ///< 18.02 kg/kmol / 997 kg/m³
  double reboiler_holdup_kmol = 0.05;            ///< M_r
  double liquid_return_fraction = 0.5;           ///< R = L_{N+1}/L_r
  double compartment_return_fraction = 0.9;      ///< r
  double heat_time_constant_min = 2.0;           ///< τ_r
  double drum_holdup_kmol = 0.05;                ///< set point of the drum level loop
  double sump_holdup_kmol = 0.10;                ///< set point of the sump level loop
  double drum_level_gain_per_min = 1.0;
  double sump_level_gain_per_min = 1.0;
  double pressure_kpa = 101.325;
  Operating nominal{0.0075, 0.0100, 0.02, 0.10};
};

class Pilot15 final : public ColumnModel {
 public:
  explicit Pilot15(Pilot15Parameters p = {});
  ~Pilot15() override;

  std::string name() const override { return "pilot15"; }
  Eigen::Index state_size() const override { return 2 * (p_.trays + 1) + 4; }
  Operating nominal() const override { return p_.nominal; }
  std::vector<std::string> state_names() const override;
  void derivative(const Eigen::VectorXd& s, const Operating& op,
                  Eigen::VectorXd& ds) const override;
  /// Central finite differences of derivative() (the bubble-point VLE has no cheap
  /// analytic derivative; the state is small).
  Eigen::MatrixXd jacobian(const Eigen::VectorXd& s, const Operating& op) const override;
  Eigen::VectorXd initial_guess(const Operating& op) const override;
  Products products(const Eigen::VectorXd& s, const Operating& op) const override;
  void check_state(const Eigen::VectorXd& s) const override;
  void integrate(Eigen::VectorXd& s, const Operating& op, double duration_min, StepMemory& steps,
                 const Tolerance& tol, IntegrationStats* stats) const override;
  void prepare() const override;

  const Pilot15Parameters& parameters() const { return p_; }
  /// Bubble temperatures (°C) of the drum (index 0) and trays 1…N.
  Eigen::VectorXd tray_temperatures_c(const Eigen::VectorXd& s) const;
  /// Francis-weir liquid outflow (kmol/min) of a tray with holdup m (kmol), composition x.
  double weir_flow(double m, double x) const;
  /// Liquid from the reboiler compartment to the sump, L_b of A.1.10, kmol/min; negative
  /// means the compartment would run dry.
  double compartment_overflow(const Eigen::VectorXd& s) const;

  class System;

 private:
  struct Workspace;
  Pilot15Parameters p_;
  EthanolWater vle_;
  double distillate_bias_ = 0.0;  // D₀ = V₀ − L₀, kmol/min
  double bottoms_bias_ = 0.0;     // B₀ = F₀ − D₀
  mutable std::unique_ptr<Workspace> work_;
};

}  // namespace excite::sim::column
