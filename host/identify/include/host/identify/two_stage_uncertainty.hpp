// SPDX-License-Identifier: MIT
#pragma once
// The two-stage estimate's gains, finished by one instrumental-variable step, and their
// standard errors (issue 41 §3; closed_loop.hpp; host/identify/README.md, "The two-stage
// gains: an instrumental-variable step").
//
// Stage 2 fits y_o on û = P_Φ u. Its prediction error ε = A_o(y_o − Σ_i Ĝ_oi û_i) holds, besides
// the noise, A_o Ĝ(u − û): the controller's answer to the noise, and the part of u that r makes
// but û does not hold when the loop is not linear in r (the MVs' clamps). Stage 2 counts the
// first as noise (its SEs are too wide), and the second is a bias, the same in every run with
// this r. The estimating equation of the instrumental-variable method with r's part of the
// loop as instruments (Söderström and Stoica, Instrumental Variable Methods for System
// Identification, 1983; in closed loop: Gilson and Van den Hof, Automatica 41 (2005) 241)
//   Σ_k z_k ε_u,k(θ) = 0,   ε_u = A_o(y_o − Σ_i G_oi(θ) u_i),   z_k = ∂ŷ_o/∂θ on u_iv,
// reads the error on the applied u, which is A_o v at the truth whatever the loop does, and z
// is a function of r: u_iv is u projected on r's Laguerre functions as û is, on fewer of them
// (closed_loop.hpp, instrument_inputs). Linearised about stage 2's estimate (J_u the sensitivities
// on u):
//   Δθ = (Zᵀ J_u)⁻¹ Zᵀ ε_u,   Cov = (Zᵀ J_u)⁻¹ Ω (Zᵀ J_u)⁻ᵀ,
// Ω the long-run covariance of z_k ε_u,k (long_run_covariance, over whitened_long_run_lags;
// default_long_run_lags when there is no noise model to whiten ε_u).

#include <Eigen/Dense>
#include <limits>

#include "host/identify/noise_model.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

/// What the step did to one row, per input (0 and 1 where it did nothing).
struct InstrumentStep {
  Eigen::VectorXd gain_step;  // ΔK
  Eigen::VectorXd se_factor;  // the gain's SE after, over stage 2's own
  // Of the step's noise model, which its SEs scale with (low_frequency_level_dof).
  double noise_level_dof = std::numeric_limits<double>::infinity();
};

/// Row `output` of a two-stage `model`, the instruments formed on `u_iv` (instrument_inputs):
/// each gain moved by the step above and its SE made √(Cov_KK + profile_variance), what a χ²₁
/// profile added where stage 2 could not tell the gain's dynamics (gain_profile.hpp). The
/// step's prefilter A_o is the noise model (fit_ar_noise, orders up to `max_noise_order`) of
/// the error on the applied u, y_o − Σ_i Ĝ_oi u_i (v's at the truth; stage 2's noise model
/// describes v + G(u − û)). The dynamics stay stage 2's (they do not move K), and so do its
/// grades and residual tests; a projected interval (gain_profile.hpp) moves with its gain.
/// Z and J_u hold the gains and, by central differences, the row's other free parameters
/// that are neither on a bound nor without an SE, each column scaled to J_u's unit norm. An
/// other parameter the instruments do not tell from the rest (the scaled ZᵀJ_u conditioned
/// beyond 10⁶) is held at stage 2's value; nothing moves where the gains themselves are not
/// determined.
InstrumentStep instrument_step_in_row(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                      const Eigen::MatrixXd& u_iv, const Eigen::VectorXd& y,
                                      const SampleLayout& layout, int max_noise_order);

}  // namespace excite::host
