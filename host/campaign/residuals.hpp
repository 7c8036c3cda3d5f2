// SPDX-License-Identifier: MIT
#pragma once
// Residual tests of an identified model on its data (Ljung's whiteness and independence
// checks): the residual's normalised autocorrelation and its cross-correlation with every
// input, with the 99 % confidence limit of a white residual, ±2.58/√N.

#include <Eigen/Core>

namespace excite::host {

struct ResidualCorrelation {
  int max_lag = 0;
  Eigen::VectorXd auto_correlation;   // r_ee(τ)/r_ee(0), τ = 0 … max_lag
  Eigen::MatrixXd cross_correlation;  // row τ + max_lag, column i: r_{u_i e}(τ), τ = −L … L,
                                      // normalised by √(r_ee(0) r_{u_i u_i}(0))
  double limit_99 = 0.0;              // 2.58/√N
};

/// Residual e (N) against inputs U (N × n), means removed; r_{ue}(τ) = (1/N) Σ_k u(k) e(k+τ)
/// (τ > 0: the input leads). An input or residual that is constant gives zeros. Throws
/// std::invalid_argument when the sizes disagree or max_lag ∉ [1, N).
ResidualCorrelation residual_correlation(const Eigen::VectorXd& e, const Eigen::MatrixXd& U,
                                         int max_lag);

}  // namespace excite::host
