// SPDX-License-Identifier: MIT
#pragma once
// The two-stage estimate's gain standard errors with stage 1's error counted (issue 41 §3;
// closed_loop.hpp; host/identify/README.md, "The two-stage standard errors").
//
// Stage 2 fits y_o on û = P_Φ u, and û is itself an estimate: û = û* + P_Φ w, with û* the
// part of u that r makes and w = u − û* the rest (under feedback, the controller's answer to
// the disturbance, correlated with the output's noise). Linearised about the estimate, the
// row's parameters move by θ̂ − θ = (JᵀJ)⁻¹ Σ_k s_k with
//   s_k = j_k ε_u,k + h_k w_k,   h = (I − P_Φ) Σ_i G_oiᵀ A_oᵀ J,
// J the row's sensitivities on the prefiltered data (row j_k, zero where not scored), ε_u =
// A_o(y_o − Σ_i Ĝ_oi u_i) the prediction error on the applied inputs, A_o the row's noise
// prefilter (noise_model.hpp) and G_oiᵀ the adjoint of element (o, i) (each segment run
// backwards; h's columns pair with w_i). Stage 2's own error term is j_k ε_k, ε = ε_u +
// A_o Ĝ(u − û); s is that minus what stage 1 adds through û, P_Φ G_oiᵀ A_oᵀ J·w, rearranged so
// that each term pairs quantities at one k (two-step estimators: Murphy and Topel, J. Bus.
// Econ. Stat. 3 (1985) 370; Newey and McFadden, Handbook of Econometrics IV (1994) §6.1).

#include <Eigen/Dense>

#include "host/identify/closed_loop.hpp"
#include "host/identify/noise_model.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

/// Row `output` of a two-stage `model` (fitted on u_hat = P(U) with the row's noise model
/// `noise`): each gain's SE widened by √(C₂/C₁)_KK where that exceeds 1, C = (JᵀJ)⁻¹ Ω (JᵀJ)⁻¹
/// and Ω the long-run covariance (long_run_covariance, default lags) of s above (C₂) or of
/// stage 2's own j_k ε_k (C₁). What stage 2 already counted (the noise model's parameters,
/// the colour left in ε) stays in the SE. Never narrowed: with a dither that r does not make
/// C₂ < C₁, but the residual that C₁ counts also carries what r makes and û misses, a bias
/// (README). J holds the gains and, by central differences, the row's other free parameters
/// that are neither on a bound nor without an SE. Returns the factors per input (1 where
/// none was applied).
Eigen::VectorXd count_stage1_in_row(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                    const Eigen::MatrixXd& u_hat, const Eigen::VectorXd& y,
                                    const ArNoiseModel& noise, const SampleLayout& layout,
                                    const ReferenceProjection& P);

}  // namespace excite::host
