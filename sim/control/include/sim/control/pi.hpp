// SPDX-License-Identifier: MIT
#pragma once
// Decentralised PI: one loop per pairing CV c → MV m, in velocity form
//
//   Δu_m(k) = Kc · [ e_c(k) − e_c(k−1) + (T/τI) · e_c(k) ],   e_c = y_sp,c − y_c,
//
// the move cut to ±max_move and the MV the plant receives (u_ctrl + known offset) to
// [min, max]. The integral is the MV itself, so a clamped MV does not wind up (the
// velocity form's anti-windup): when the error turns, the MV leaves its limit at once.
// Kc in MV units per CV unit, with the sign of the paired gain (a negative gain needs a
// negative Kc); τI in minutes; T the sample time in minutes. An MV with no pairing stays
// at 0 (plus its offset). At reset every error is 0 (at rest at the operating point).

#include <vector>

#include "sim/control/controller.hpp"
#include "sim/control/dmc.hpp"

namespace excite::sim::control {

struct PiLoop {
  int cv = 0;                 // 0-based
  int mv = 0;                 // 0-based
  double gain = 0.0;          // Kc ≠ 0
  double integral_min = 1.0;  // τI > 0, minutes
};

struct PiSettings {
  double sample_time_min = 1.0;
  int inputs = 0;              // n
  int outputs = 0;             // p
  std::vector<PiLoop> loops;   // each CV and each MV in at most one loop
  std::vector<MvSettings> mv;  // n entries (move_suppression unused)
};

class PiController final : public Controller {
 public:
  /// Throws std::invalid_argument naming the setting (pairing[i].*, mv[j].*).
  explicit PiController(PiSettings settings);

  int inputs() const noexcept override { return settings_.inputs; }
  int outputs() const noexcept override { return settings_.outputs; }
  double sample_time_min() const noexcept override { return settings_.sample_time_min; }
  void reset() noexcept override;
  StepReport step(std::span<const double> y, std::span<const double> y_sp,
                  std::span<const double> known_offsets,
                  std::span<double> u_ctrl) noexcept override;
  std::span<const MvStatus> mv_status() const noexcept override { return status_; }

  const PiSettings& settings() const noexcept { return settings_; }

 private:
  PiSettings settings_;
  std::vector<double> error_prev_;  // per loop
  std::vector<double> u_prev_;      // per MV
  std::vector<MvStatus> status_;
};

}  // namespace excite::sim::control
