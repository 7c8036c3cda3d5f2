// SPDX-License-Identifier: MIT
#pragma once
// Predictive amplitude control (issue 26 §2): before a segment of excitation goes out, each
// CV's excursion is predicted with the current model and its uncertainty, and the segment is
// scaled so the prediction ± k σ stays inside the CV test limits.
//
// The prediction runs over the segment and the model's settling time after it (the inputs
// back at their baselines there, as the gateway leaves them when a run ends), on top of the
// response still coming from the history already applied:
//   y_j(t; α) = h_j(t) + α s_j(t),
// h the model's response to the history (followed by zeros), s its response to the segment
// (after the history's rows). Its variance is linearised in every element's parameters,
//   σ_j²(t; α) = Σ_i (∂h_ji + α ∂s_ji)ᵀ C_ji (∂h_ji + α ∂s_ji) + the row's gain covariances
//   between elements,
// C_ji the element's parameter covariance (ElementEstimate::covariance; NaN rows, a parameter
// on its bound, count as known), ∂ by central differences of the simulated response. Each
// limit y_j ± k σ_j ≤ high_j (≥ low_j) is convex in α (σ_j is the norm of an affine function
// of α), so the admissible scales form an interval that holds 0 when the history alone is
// admissible; the largest is found by bisection.

#include <Eigen/Dense>
#include <string>

#include "host/identify/model.hpp"

namespace excite::host {

/// Per output, the CV test limits as deviations from the baseline (the units of dy):
/// low_j < 0 < high_j.
struct CvLimits {
  Eigen::VectorXd low;
  Eigen::VectorXd high;
};

struct ScaleOptions {
  double k_sigma = 2.0;    // the band the limits must hold: prediction ± k σ
  double max_scale = 1.0;  // the segment is never scaled up beyond this
};

struct SegmentScale {
  double scale = 0.0;             // α ∈ [0, max_scale]: multiply the segment by it
  int binding_output = -1;        // the output whose limit stops a larger α (-1: none does)
  Eigen::Index binding_row = -1;  // its row, counted from the segment's first row
  bool binding_high = false;      // its high limit binds (else its low one)
  bool history_leaves = false;    // α = 0 because the history alone leaves a limit
  std::string reason;             // why α < max_scale, in words; "" otherwise
};

/// The largest α ≤ max_scale for which every output's prediction ± k σ stays within its
/// limits over the segment's rows and the model's settling time after it. `history`: the
/// excitation already applied (rows × model.inputs, deviations from the baselines, may have
/// 0 rows); `segment`: the next segment's excitation (rows ≥ 1 × model.inputs). α = 0 with a
/// reason when the history alone is predicted to leave a limit, when an element the segment
/// moves was not estimated, or when a parameter's uncertainty is unbounded (inf).
/// Throws std::invalid_argument naming the field, its value and what was expected for
/// mismatched sizes, non-finite values, limits that do not hold 0, or bad options.
SegmentScale scale_segment(const IdentifiedModel& model, const Eigen::MatrixXd& history,
                           const Eigen::MatrixXd& segment, const CvLimits& limits,
                           const ScaleOptions& options = {});

}  // namespace excite::host
