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

/// Lags of the residual tests, as MATLAB's `resid` (25).
inline constexpr int kResidualTestLags = 25;

/// Ljung's two portmanteau tests of one output's residual at the 1 % level (System
/// Identification, 2nd ed., §16.6), what a grade (grade.hpp) asks of an element:
///  - whiteness: Q = N(N+2) Σ_{τ=1}^{L} r_ee(τ)²/(N − τ) (Ljung–Box) against χ²₀.₉₉(L);
///  - independence of input i: S_i = N r̂ᵀ R̂_u⁻¹ r̂, r̂ = (r_{u_i e}(0), …, r_{u_i e}(L)) and
///    R̂_u the input's (L+1)-Toeplitz autocorrelation, against χ²₀.₉₉(L + 1). R̂_u⁻¹ makes
///    the test hold for a coloured input (a PRBS held for T_sw); with a white residual each
///    r_{ue}(τ) has variance 1/N whatever the input, but neighbouring lags are correlated
///    as the input is.
/// A constant input has no statistic (0, and independent). Inputs the fit did not use may
/// be passed; their statistic is computed all the same.
struct ResidualTests {
  int lags = 0;
  double whiteness = 0.0;           // Q
  double whiteness_limit = 0.0;     // χ²₀.₉₉(L)
  Eigen::VectorXd independence;     // S_i per input
  double independence_limit = 0.0;  // χ²₀.₉₉(L + 1)

  bool white() const { return whiteness <= whiteness_limit; }
  bool independent_of(Eigen::Index input) const {
    return independence(input) <= independence_limit;
  }
};

/// The tests of residual e (N) against inputs U (N × n) over `lags` lags. Throws
/// std::invalid_argument when the sizes disagree or lags ∉ [1, N/2).
ResidualTests residual_tests(const Eigen::VectorXd& e, const Eigen::MatrixXd& U,
                             int lags = kResidualTestLags);

}  // namespace excite::host
