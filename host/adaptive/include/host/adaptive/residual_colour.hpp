// SPDX-License-Identifier: MIT
#pragma once
// Honest intervals when the residuals are not white (issue 26 §3, the stop rule).
//
// The identified covariance σ̂² (JᵀJ)⁻¹ assumes white residuals. Model error (a structure
// that cannot follow the plant, a nonlinear column, a record shorter than the slow modes)
// leaves residuals that are coloured, mostly at low frequency, where a gain's information
// is; the gain's variance is then larger by about the residual's long-run variance ratio
//   f_j = Σ_{|k| ≤ L} (1 − |k|/(L + 1)) ρ_j(k)      (Bartlett window, ρ_j the residual's
//                                                     autocorrelation of output j)
// — 2π S_e(0) / σ_e², the spectral density at frequency 0 over the variance (Newey & West
// 1987). The stop rule multiplies row j's gain covariance by max(1, f_j) before the
// singular values, directions and minors are propagated (gain_uncertainty.hpp): white
// residuals leave the intervals as identified; coloured ones widen them.

#include <Eigen/Core>

#include <optional>

#include "host/identify/identify.hpp"

namespace excite::host {

/// f_j of every output's residual y − ŷ (the model simulated on U from rest) over lags
/// 1 … L, L = min(lags, N/4). A NaN residual (an element not estimated) gives NaN. Throws
/// std::invalid_argument for mismatched sizes or lags < 1.
Eigen::VectorXd long_run_variance_ratio(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                                        const Eigen::MatrixXd& Y, int lags);

/// The G(0) uncertainty with row j's gain covariance times max(1, ratio_j); nullopt when the
/// result has no G(0) uncertainty or a ratio is not finite.
std::optional<GainUncertainty> inflated_gain_uncertainty(const IdentificationResult& result,
                                                         const Eigen::VectorXd& ratio);

}  // namespace excite::host
