// SPDX-License-Identifier: MIT
#pragma once
// One output row's gains: the prediction's sensitivity to them, and the widening of their
// standard errors where identify()'s σ̂²(JᵀJ)⁻¹ is too small (issue 41 §3; used by
// closed_loop.hpp and noise_model.hpp).
//
// ŷ_o = Σ_i K_oi · h_oi ∗ u_i with h_oi element (o, i)'s unit-gain response: ŷ_o is linear in
// the row's gains, so ∂ŷ_o/∂K_oi = h_oi ∗ u_i exactly.

#include <Eigen/Dense>
#include <vector>

#include "host/identify/model.hpp"
#include "host/identify/segments.hpp"

namespace excite::host {

/// u through one discretised element, each segment from rest.
Eigen::VectorXd element_output(const sim::DiscreteTerm& g, const Eigen::VectorXd& u,
                               const std::vector<Segment>& segments);

/// ŷ's column `output`: the row's estimated elements driven by U (N × n), each segment from
/// rest. An element not estimated contributes nothing (callers pass rows they can simulate).
Eigen::VectorXd simulate_row(const IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                             const std::vector<Segment>& segments);

struct RowGainSensitivity {
  Eigen::MatrixXd X;      // N × used.size(): column c is ∂ŷ_o/∂K_{o, used[c]}
  std::vector<int> used;  // the row's inputs whose gain is estimated, nonzero, with a finite SE
};

/// The sensitivities of row `output`'s prediction to its gains, U (N × n), per segment.
RowGainSensitivity row_gain_sensitivity(const IdentifiedModel& model, int output,
                                        const Eigen::MatrixXd& U,
                                        const std::vector<Segment>& segments);

/// Multiplies the standard error of K_{output, i} by factor(i) (each > 0) for every input i,
/// with the element's covariance row and column and the row's gain covariance.
void scale_row_gain_ses(IdentifiedModel& model, int output, const Eigen::VectorXd& factor);

/// The Bartlett-weighted long-run covariance of the rows g_k of g (Newey and West,
/// Econometrica 55 (1987) 703): Σ_{|l|≤L} (1 − |l|/(L+1)) Σ_k g_k g_{k−l}ᵀ, L = max_lag.
Eigen::MatrixXd long_run_covariance(const Eigen::MatrixXd& g, Eigen::Index max_lag);

/// The lags the long-run covariances here take by default over N rows: min(200, N/10).
Eigen::Index default_long_run_lags(Eigen::Index rows);

/// The lags for a score whose error its noise model has whitened: Newey and West's rule for
/// the Bartlett kernel, ⌊4 (N/100)^(2/9)⌋ (Review of Economic Studies 61 (1994) 631), at
/// least 1. More lags than the correlation left add only the estimate's own noise to Ω.
Eigen::Index whitened_long_run_lags(Eigen::Index rows);

/// Row `output`'s gain SEs widened (never narrowed) for a coloured residual: the sandwich
/// ("HAC", Newey and West, Econometrica 55 (1987) 703) with Bartlett weights over `max_lag`
/// lags (0: min(200, N/10)),
///   Cov = (XᵀX)⁻¹ [Σ_{|l|≤L} (1 − |l|/(L+1)) Σ_k x_k e_k e_{k−l} x_{k−l}ᵀ] (XᵀX)⁻¹,
/// X the row's gain sensitivities and e = y − ŷ_o on the scored rows of `layout`; each
/// gain's variance becomes Cov_ii where that exceeds σ̂²(XᵀX)⁻¹_ii. Returns the largest
/// factor applied to an SE (1: none).
double widen_row_for_coloured_residual(IdentifiedModel& model, int output, const Eigen::MatrixXd& U,
                                       const Eigen::VectorXd& y, const SampleLayout& layout,
                                       int max_lag = 0);

}  // namespace excite::host
