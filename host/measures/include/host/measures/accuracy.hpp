// SPDX-License-Identifier: MIT
#pragma once
// The accuracy criterion of issue 29: an identified G(0) (SPEC §3, (5.2.1)) is accurate
// enough when, against the true plant's,
//   - every principal minor has the true minor's sign (integral controllability),
//   - the smallest singular value σ_n is within ±20 % of the true one, and
//   - the weakest input direction v_n is within 10° of the true one (sign ignored).

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "host/measures/gain_directions.hpp"

namespace excite::host {

inline constexpr double kSigmaTolerance = 0.20;     // |σ̂_n − σ_n| ≤ 0.20 σ_n
inline constexpr double kAngleToleranceDeg = 10.0;  // ∠(v̂_n, ±v_n) ≤ 10°

/// The true plant, as the criterion needs it.
struct TruePlant {
  GainAnalysis gain;           // SVD of the true G(0); square
  std::vector<double> minors;  // every principal minor, in principal_minor_values' order
};
/// Throws std::invalid_argument when G(0) is not square.
TruePlant true_plant_of(const Eigen::MatrixXd& gain);

/// det G[S,S] for every non-empty index set S, S ordered by its bit mask (1, 2, 3, …):
/// 2^n − 1 values for an n × n matrix.
std::vector<double> principal_minor_values(const Eigen::MatrixXd& gain);

struct Accuracy {
  bool gain_identified = false;    // every K estimated (else the rest is NaN / false)
  double sigma_n_error = 0.0;      // (σ̂_n − σ_n) / σ_n, signed
  double weakest_angle_deg = 0.0;  // ∠(v̂_n, ±v_n) in degrees, 0…90
  bool minor_signs_right = false;
  bool met = false;  // all three
};

/// Judges an identified G(0) (empty: not identified, not met).
Accuracy judge(const TruePlant& truth, const std::optional<GainAnalysis>& identified);

}  // namespace excite::host
