// SPDX-License-Identifier: MIT
#pragma once
// The adaptive plant test (issue 26 §3): excite, re-estimate, re-aim, resize, until the model
// is good enough.
//
//   segment 0   the prior's plain PRBS (prbsUnc, at the engineer's amplitude: the design's
//               times first_scale), H rows, or
//               the shortest record identify takes (minimum_samples) when that is longer;
//   after each segment, once the record is long enough to identify (identify.hpp
//   minimum_samples):
//     1. identify from all data so far (structures chosen per element, SPEC §6 bound β·τ_H);
//     2. the stop rule (confidence.hpp): the Monte Carlo accuracy criterion at 95 %
//        confidence from the identified gains' covariance, widened for coloured residuals
//        (residual_colour.hpp, Bartlett window of one settling time β·τ_H), agreeing with
//        the previous estimate → stop when it holds;
//     3. the next segment: the next H rows of the same m-sequences, mixed along V̂ Σ̂⁻¹ of the
//        identified G(0), direction i weighted by its need (the least certain direction at
//        full amplitude, none below the floor), then sized by predictive amplitude control
//        (amplitude_control.hpp) when CV limits are given;
//   stop at the maximum length otherwise.
// A record too short to identify, or an identified G(0) without a usable uncertainty,
// continues plain. Under CV limits, a model sizes a segment only once it agrees with the
// estimate before it (confidence.hpp; a young model in a wrong optimum has a tight band around
// a wrong response): until then the segments are plain at the engineer's amplitude, and the
// scale is the smaller of the latest two models'. When amplitude control cannot judge a
// directional segment (an element
// not estimated, an unbounded uncertainty) the next segment is plain at the engineer's
// amplitude; when it predicts that the history alone leaves a limit (± k σ of a young
// model), the next segment holds the operating point (scale 0) while the data still come
// in, and a second such prediction in a row stops the test.
//
// Everything decided is in the result (each re-estimate, each segment's mix, weights, scale
// and why, why it stopped) and reported as it happens to an observer (the decision log and the
// operator's view, decision_log.hpp).

#include <Eigen/Core>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "host/adaptive/amplitude_control.hpp"
#include "host/adaptive/confidence.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/identify/identify.hpp"

namespace excite::host {

/// What one segment did to the plant: rows × inputs and rows × outputs, deviations from the
/// baselines; dy as measured. dy_true: the outputs without measurement noise where the
/// runner knows them (a simulation), else empty.
struct MeasuredSegment {
  Eigen::MatrixXd du, dy, dy_true;
};

/// Applies segments to a plant, one after the other without a pause, and measures them.
class SegmentRunner {
 public:
  virtual ~SegmentRunner() = default;
  /// Runs `segment` (its table, row by row, on top of the operating point) and returns what
  /// was measured over its rows. Throws std::runtime_error when the plant cannot take it.
  virtual MeasuredSegment run(const plan::Plan& segment) = 0;
};

struct AdaptiveOptions {
  double segment_min = 0.0;     // H: re-estimate after every H minutes (0: 4 τ_H), rounded up
                                // to whole PRBS bits
  double max_length_min = 0.0;  // stop here at the latest (0: the prior's prbsUnc length)
  StopRule rule;
  double first_scale = 1.0;        // the plain segments' amplitude, a share of the prior's
                                   // prbsUnc (the engineer's choice; not resized)
  double weight_floor = 0.25;      // no direction's weight below this (confidence.hpp)
  std::optional<CvLimits> limits;  // CV test limits; none: segments are not resized
  ScaleOptions scale;
  IdentifyOptions identify;  // max_time_constant_min 0 → β·τ_H of the prior
};

/// One identification of the data so far.
struct Reestimate {
  int after_segment = 0;    // the segments 0 … after_segment are in it
  long long samples = 0;    // rows identified
  double length_min = 0.0;  // samples · T
  IdentificationResult result;
  Eigen::VectorXd colour;                      // long-run variance ratio per output (NaN: none)
  std::optional<GainUncertainty> uncertainty;  // the G(0) uncertainty the rule reads: the
                                               // result's, rows inflated by colour (rule.colour)
  Confidence confidence;
  std::optional<double> predicted_stop_min;  // confidence.hpp: length · need²
};

/// How one segment was made.
struct SegmentDecision {
  int index = 0;
  long long first_row = 0;  // in the whole record, when decided (a gateway in real time may
                            // log held rows before the segment's first row: InboxRunner)
  std::uint32_t rows = 0;
  bool directional = false;  // along V̂ Σ̂⁻¹ of estimate `from_estimate` (closed loop: along
                             // the prior's output directions when -1); else plain
  int from_estimate = -1;    // index into AdaptiveResult::estimates; -1: none
  Eigen::VectorXd weights;   // per direction (directional) or per input (plain: all 1)
  double scale = 1.0;        // the mix's factor: first_scale for plain segments, amplitude
                             // control's α for sized ones, 0 for a hold
  std::string why;           // the decision in words
  plan::Plan plan;           // what goes to the gateway
};

/// What the stop rule reads of an estimate (pointers into it).
GainEvidence evidence_of(const Reestimate& estimate);

/// Index of the latest of `estimates` with a usable G(0) uncertainty made on at most
/// `longest_min` of data (default: any); -1: none.
int latest_aimable(const std::vector<Reestimate>& estimates,
                   double longest_min = std::numeric_limits<double>::infinity());

/// Sets e.confidence (the stop rule, confidence.hpp, against the latest usable estimate made
/// on at least `settling_min` less data than e) and e.predicted_stop_min. e.result and
/// e.uncertainty must be set.
void judge_estimate(Reestimate& e, const std::vector<Reestimate>& earlier, double settling_min,
                    const StopRule& rule);

struct AdaptiveResult {
  std::vector<SegmentDecision> segments;
  std::vector<Reestimate> estimates;
  bool criterion_met = false;  // stopped because the stop rule held
  std::string stop_reason;
  double sample_time_min = 0.0;
  Eigen::MatrixXd U, Y, Y_true;  // the whole test so far (Y_true empty unless the runner knows)
  Eigen::MatrixXd R;             // with the controller on: r, the setpoint offsets (rows × CVs)
  // Under CV limits, per output: the measured rows outside its limits, and the measured
  // deviation furthest outside them (NaN: none). Empty without limits.
  std::vector<long long> rows_outside_limits;
  Eigen::VectorXd worst_outside_limits;

  double length_min() const { return static_cast<double>(U.rows()) * sample_time_min; }
};

/// A new estimate of the record so far, after segment `after_segment`: its length set, the
/// rest for the caller to fill.
Reestimate new_estimate(const AdaptiveResult& so_far, int after_segment);

/// Counts the rows of `dy` (rows × outputs) outside `limits` into result.rows_outside_limits
/// and result.worst_outside_limits (sized on first use); returns this dy's count per output.
std::vector<long long> count_outside_limits(const Eigen::MatrixXd& dy, const CvLimits& limits,
                                            AdaptiveResult& result);

/// Told of every step as it happens (the result so far, with the new entry last).
class AdaptiveObserver {
 public:
  virtual ~AdaptiveObserver() = default;
  virtual void decided(const AdaptiveResult& /*so_far*/) {}    // a segment about to run
  virtual void estimated(const AdaptiveResult& /*so_far*/) {}  // a re-estimate
  virtual void stopped(const AdaptiveResult& /*result*/) {}
};

/// What run_adaptive_test checks before its first segment, without running anything: the
/// options (CV limits LOW < 0 < HIGH, at most 10⁸ samples), and under CV limits that the
/// plain segments sized by the prior's G(0) keep at least 1 % of the engineer's amplitude
/// (else the test could not excite the plant inside them). Throws std::invalid_argument.
void check_adaptive_test(const PriorKnowledge& prior, const AdaptiveOptions& options);

/// Runs the adaptive test on `runner` from validated prior knowledge (τ_L, τ_H, the
/// inputs' amplitudes and limits; G(0) only sizes the first, plain segment). Throws
/// std::invalid_argument for bad options or a prior the designs refuse.
AdaptiveResult run_adaptive_test(const PriorKnowledge& prior, SegmentRunner& runner,
                                 const AdaptiveOptions& options,
                                 AdaptiveObserver* observer = nullptr);

}  // namespace excite::host
