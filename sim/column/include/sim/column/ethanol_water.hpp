// SPDX-License-Identifier: MIT
#pragma once
// Vapour–liquid equilibrium of ethanol (1) – water (2) at constant pressure: modified
// Raoult's law y₁ P = γ₁ x₁ P₁ˢᵃᵗ(T) at the bubble point, with van Laar activity
// coefficients and Antoine vapour pressures (constants and sources in sim/column/README.md).
// Gives the non-constant equilibrium y*(x) of thesis A.1.4 (α = α(x), with the azeotrope).

namespace excite::sim::column {

struct BubblePoint {
  double temperature_c;  ///< bubble temperature, °C
  double y;              ///< equilibrium vapour mole fraction of ethanol y*(x)
};

class EthanolWater {
 public:
  explicit EthanolWater(double pressure_kpa = 101.325) : pressure_kpa_(pressure_kpa) {}

  /// Bubble point of a liquid with ethanol mole fraction x (clamped to [0, 1]); Newton on
  /// T to machine precision, so y*(x) is smooth enough for finite-difference Jacobians.
  BubblePoint bubble_point(double x) const;
  double pressure_kpa() const { return pressure_kpa_; }

  /// Vapour pressures (kPa) of ethanol and water at t_c (°C), Antoine.
  static double ethanol_pressure_kpa(double t_c);
  static double water_pressure_kpa(double t_c);

 private:
  double pressure_kpa_;
};

}  // namespace excite::sim::column
