// SPDX-License-Identifier: MIT
#pragma once
// Which samples the output-error fit simulates and which it scores (issue 10 §6, issue 13).
//
// The data are split into segments [begin, end): the model is simulated from rest at each
// segment's begin (a run's start, a plant restart, ticks skipped, a span whose inputs are not
// known), so a model's state never crosses a restart. Inside a segment the simulation is
// continuous: rows whose outputs are not to be trusted (suspended, stale, …) are driven by
// their logged inputs but carry weight 0 in the cost, which keeps the model's state right
// across them — the segment's initial state for the rows after the span is the model's own
// response to the logged inputs before it. The rule that maps run-log flags to this layout
// is in run_data.hpp.

#include <Eigen/Dense>
#include <span>
#include <vector>

#include "host/identify/element.hpp"

namespace excite::host {

struct Segment {
  Eigen::Index begin = 0;  // first row; the model starts from rest here
  Eigen::Index end = 0;    // one past the last row
};

/// The fit's sample layout over N rows: segments partition 0 … N−1 in order; `weight` is
/// 1 for a row in the cost and 0 for a row only simulated.
struct SampleLayout {
  std::vector<Segment> segments;
  Eigen::VectorXd weight;

  /// One segment over all N rows, every row scored (the plant at rest before row 0).
  static SampleLayout whole(Eigen::Index rows);

  Eigen::Index rows() const { return weight.size(); }
  /// Rows in the cost.
  Eigen::Index scored() const;
  /// Throws std::invalid_argument unless the segments partition 0 … rows()−1 in order and
  /// every weight is 0 or 1.
  void check() const;
  /// The scored rows of v, in order.
  Eigen::VectorXd scored_rows(const Eigen::VectorXd& v) const;
  /// The rows of M (rows() rows) that are scored within [begin, end), in order.
  Eigen::MatrixXd scored_rows(const Eigen::MatrixXd& M, Eigen::Index begin, Eigen::Index end) const;
};

/// The scored rows of Y, each segment's about that segment's own mean, pooled in order (a
/// restart may move the operating point; an offset between segments is not excitation). One
/// segment scoring every row: Y about its mean. Segments without scored rows add nothing.
Eigen::MatrixXd scored_about_segment_means(const Eigen::MatrixXd& Y, const SampleLayout& layout);

/// A trend fitted with the model (issue 13 §1): per segment an offset, or an offset and a
/// slope, of each output that the (6.1.1) model does not explain (an unmeasured disturbance,
/// a drifting sensor). They are linear parameters: eliminated exactly by projecting the
/// output error and its Jacobian on the orthogonal complement of their columns (variable
/// projection; the columns do not depend on the model's parameters, so the projected
/// Jacobian is exact).
enum class Trend { none, offset, linear };

/// Orthonormal columns (N × r) spanning the trend of every segment with scored rows, zero
/// on rows that are not scored; N × 0 for Trend::none without transients.
/// `transient_samples`: the initial state of every segment (a record that starts mid-test,
/// issue 18 §2): per segment an offset (the MV baselines' error settles to one) and the
/// decays exp(−k/τ) for each τ given (in samples), which span the free response of the
/// plant's modes from whatever state the segment starts in.
Eigen::MatrixXd trend_basis(const SampleLayout& layout, Trend trend,
                            const std::vector<double>& transient_samples = {});

/// y = G u per segment, each from rest.
void simulate_segments(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y,
                       const std::vector<Segment>& segments);

/// y = Σ_e gains[e]·G_e u_e per segment, each from rest: rounding for rounding y = 0 and then
/// y += gains[e]·z_e for e = 0, 1, … with z_e from simulate_segments(), but the elements'
/// recursions run side by side (sim::tdf2_accumulate_sum). `scratch` holds the delayed inputs;
/// its contents on return are unspecified.
void simulate_sum_segments(std::span<const sim::DiscreteTerm* const> terms,
                           std::span<const double> gains,
                           std::span<const std::span<const double>> inputs, std::span<double> y,
                           const std::vector<Segment>& segments, std::vector<double>& scratch);

/// all_pole_filter() on each column of `x` per segment, each from rest, with the column's own
/// coefficients a[column]: the same values, the columns' recursions run side by side (each alone
/// waits on its latency).
void all_pole_filter_columns(std::span<const std::array<double, kMaxPoles>> a,
                             Eigen::Ref<Eigen::MatrixXd> x, const std::vector<Segment>& segments);

/// One term c · src(k − lag) of lagged_sum(); `src` has the rows of the layout.
struct LaggedTerm {
  double c = 0.0;
  const double* src = nullptr;
  Eigen::Index lag = 0;
};

/// dst(k) = Σ_t c_t · src_t(k − lag_t) over the terms whose k − lag_t lies in k's segment,
/// summed from 0 in the terms' order: rounding for rounding dst = 0 and then add_lagged() per
/// term, in one pass over dst.
void lagged_sum(Eigen::Ref<Eigen::VectorXd> dst, std::span<const LaggedTerm> terms,
                const std::vector<Segment>& segments);

/// dst(k) += c · src(k − lag) for every k whose k − lag lies in the same segment.
void add_lagged(Eigen::Ref<Eigen::VectorXd> dst, const Eigen::VectorXd& src, Eigen::Index lag,
                double c, const std::vector<Segment>& segments);

}  // namespace excite::host
