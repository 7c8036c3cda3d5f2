// SPDX-License-Identifier: MIT
#include "host/adaptive/closed_loop_adaptive.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "host/adaptive/segments.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/design/table.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {

ClosedLoopPlant::ClosedLoopPlant(sim::Plant& plant, sim::control::Controller& controller,
                                 ClosedLoopOptions loop, SimulationOptions noise,
                                 double sample_time_min)
    : plant_(plant),
      controller_(controller),
      loop_(std::move(loop)),
      noise_(noise),
      sample_time_min_(sample_time_min) {
  loop_.excitation = runlog::Excitation::setpoint;
}

SimulatedRun ClosedLoopPlant::run(const Eigen::MatrixXd& r, bool noise_free) {
  SimulationOptions noise = noise_;
  if (noise_free) {
    noise.noise_variance = 0.0;
    noise.disturbance_std = 0.0;
  }
  return simulate_closed_loop(r, "excite test", sample_time_min_, plant_, controller_, loop_,
                              noise);
}

namespace {

std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

void check_closed_loop_options(const PriorKnowledge& prior, const ClosedLoopAdaptiveOptions& o) {
  const auto n = static_cast<Eigen::Index>(prior.input_count());
  if (!o.adaptive.limits || o.adaptive.limits->low.size() != n || prior.gain.rows() != n ||
      prior.gain.cols() != n) {
    throw std::invalid_argument(
        "CV limits = " +
        (o.adaptive.limits ? std::to_string(o.adaptive.limits->low.size()) : std::string("none")) +
        " for a " + std::to_string(prior.gain.rows()) + "x" + std::to_string(prior.gain.cols()) +
        " plant, expected one per CV of a square plant (r is sized by them)");
  }
  for (Eigen::Index j = 0; j < n; ++j) {
    if (!(o.adaptive.limits->low(j) < 0.0 && o.adaptive.limits->high(j) > 0.0)) {
      throw std::invalid_argument(
          "CV " + std::to_string(j + 1) + " limits = " + short_number(o.adaptive.limits->low(j)) +
          ":" + short_number(o.adaptive.limits->high(j)) + ", expected LOW < 0 < HIGH");
    }
  }
  if (!(o.limit_fraction > 0.0 && o.limit_fraction <= 1.0)) {
    throw std::invalid_argument("limit fraction = " + short_number(o.limit_fraction) +
                                ", expected a share in (0, 1]");
  }
  if (!(o.mv_fraction >= 0.0 && std::isfinite(o.mv_fraction))) {
    throw std::invalid_argument("MV fraction = " + short_number(o.mv_fraction) + ", expected >= 0");
  }
}

// The closed-loop test, one segment after the other (closed_loop_adaptive.hpp).
class ClosedLoopTest {
 public:
  ClosedLoopTest(const PriorKnowledge& prior, ClosedLoopPlant& loop,
                 const ClosedLoopAdaptiveOptions& o)
      : prior_(prior), loop_(loop), o_(o), sources_(segment_sources(prior)) {
    check_closed_loop_options(prior, o);
    const plan::Plan& plain = *sources_.plain.plan;
    result_.sample_time_min = plain.meta.sample_time_min;
    rows_ = whole_bit_rows(
        plain, o.adaptive.segment_min > 0.0 ? o.adaptive.segment_min : 4.0 * prior.tau_high_min);
    max_rows_ = o.adaptive.max_length_min > 0.0
                    ? static_cast<long long>(
                          std::ceil(o.adaptive.max_length_min / result_.sample_time_min - 1e-9))
                    : static_cast<long long>(plain.recipe.samples);
    identify_ = o.adaptive.identify;
    if (identify_.max_time_constant_min <= 0.0)
      identify_.max_time_constant_min = prior.beta * prior.tau_high_min;
    // The stop rule reads the covariance, not the reported intervals, and every segment is
    // identified again: no projections (host/identify/README.md, "The reported 95 % interval").
    identify_.project_gains = false;
    const CvLimits& l = *o.adaptive.limits;
    amplitude_ = cv_amplitude(l.low, l.high, o.limit_fraction);
  }

  AdaptiveResult run() {
    for (int index = 0;; ++index) {
      const Reestimate* last = result_.estimates.empty() ? nullptr : &result_.estimates.back();
      add_segment(index, last);
      const SimulatedRun run = loop_.run(R_);
      result_.U = run.du;
      result_.Y = run.dy;
      const Reestimate* e = reestimate(index);
      if (e != nullptr && e->confidence.met)
        return stop(true, "the stop rule holds: the accuracy criterion at 95 % confidence");
      if (result_.U.rows() >= max_rows_) {
        return stop(false, "the maximum length, " + minutes(max_rows_) + ", is reached" +
                               (e != nullptr ? "; still missing: " + e->confidence.missing : ""));
      }
    }
  }

 private:
  std::string minutes(long long rows) const {
    return short_number(static_cast<double>(rows) * result_.sample_time_min) + " min";
  }

  // Rows [first, first + rows) of the prior's prbsUnc sources from prbs_phase on, each ±1.
  Eigen::MatrixXd sources(long long first, std::uint32_t rows) const {
    const std::uint64_t hold = sources_.plain.plan->recipe.sources[0].prbs.hold_samples;
    const plan::Plan cut = cut_segment(
        *sources_.plain.plan, static_cast<std::uint64_t>(first) + o_.prbs_phase * hold, rows);
    Eigen::MatrixXd s = make_table(cut.recipe);
    for (Eigen::Index i = 0; i < s.cols(); ++i) {
      const double peak = s.col(i).cwiseAbs().maxCoeff();
      if (peak > 0.0) s.col(i) /= peak;
    }
    return s;
  }

  // Plain or along the prior's Ŵ (no usable estimate yet), or re-aimed along Ŵ diag(w) of the
  // latest usable one; the MVs' room cut last.
  void add_segment(int index, const Reestimate* last) {
    SegmentDecision d;
    d.index = index;
    d.first_row = R_.rows();
    d.rows = static_cast<std::uint32_t>(std::min<long long>(rows_, max_rows_ - d.first_row));
    const int aim = last != nullptr ? latest_aimable(result_.estimates) : -1;
    const auto n = static_cast<Eigen::Index>(prior_.input_count());
    Eigen::MatrixXd mix = Eigen::MatrixXd::Identity(n, n);  // CV j × source i
    Eigen::MatrixXd gain = prior_.gain;
    d.weights = Eigen::VectorXd::Ones(n);
    if (aim >= 0) {
      const Reestimate& e = result_.estimates[static_cast<std::size_t>(aim)];
      d.directional = true;
      d.from_estimate = aim;
      d.weights = direction_weights(e.confidence, static_cast<int>(n), o_.adaptive.weight_floor);
      mix = e.result.gain->output_directions * d.weights.asDiagonal();
      gain = e.result.gain->gain;
      d.why = "along the output directions of the estimate at " + minutes(e.samples) +
              ", weights (need over the largest)";
      for (Eigen::Index i = 0; i < n; ++i) d.why += " " + short_number(d.weights(i));
    } else if (o_.prior_directions) {
      d.directional = true;  // from_estimate -1: the prior's directions
      mix = analyse_gain(prior_.gain).output_directions;
      d.why = "along the prior's output directions, equal weights, at " +
              short_number(o_.limit_fraction) + " of each CV's test limit" +
              (last == nullptr ? "" : " (no usable G(0) yet)");
    } else {
      d.why = "plain: every CV its own PRBS at " + short_number(o_.limit_fraction) +
              " of its test limit" + (last == nullptr ? "" : " (no usable G(0) yet)");
    }
    if (d.directional) {  // D: each CV's row to a peak of 1 (|r_j| ≤ a_j)
      for (Eigen::Index j = 0; j < n; ++j) mix.row(j) /= mix.row(j).cwiseAbs().sum();
    }
    Eigen::MatrixXd r = sources(d.first_row, d.rows) * mix.transpose() * amplitude_.asDiagonal();
    d.scale = mv_room(gain, r, d.why);
    R_.conservativeResize(R_.rows() + r.rows(), n);
    R_.bottomRows(r.rows()) = d.scale * r;
    result_.segments.push_back(std::move(d));
  }

  double mv_room(const Eigen::MatrixXd& gain, const Eigen::MatrixXd& r, std::string& why) const {
    const ClosedLoopOptions& loop = loop_.loop();
    const double alpha = mv_room_scale(gain, r, loop.mv_min, loop.mv_max, o_.mv_fraction);
    if (alpha < 1.0) why += "; scale " + short_number(alpha) + " for the MVs' room";
    return alpha;
  }

  const Reestimate* reestimate(int after_segment) {
    const int n = prior_.input_count();
    if (result_.U.rows() < minimum_samples(n, result_.sample_time_min, identify_)) return nullptr;
    Reestimate e = new_estimate(result_, after_segment);
    const SampleLayout whole = SampleLayout::whole(result_.U.rows());
    const double T = result_.sample_time_min;
    // The stop rule reads the gain SEs: the two-stage ones are the IV step's.
    e.result = o_.two_stage
                   ? identify_two_stage(result_.U, R_, result_.Y, T, whole, identify_).fit.result
                   : identify_with_noise_model(result_.U, result_.Y, T, whole, identify_).result;
    e.uncertainty = e.result.gain_uncertainty;
    judge_estimate(e, result_.estimates, prior_.beta * prior_.tau_high_min, o_.adaptive.rule);
    result_.estimates.push_back(std::move(e));
    return &result_.estimates.back();
  }

  AdaptiveResult stop(bool met, std::string reason) {
    result_.criterion_met = met;
    result_.stop_reason = std::move(reason);
    result_.Y_true = loop_.run(R_, true).dy;
    result_.R = R_;
    count_outside_limits(result_.Y, *o_.adaptive.limits, result_);
    return std::move(result_);
  }

  const PriorKnowledge& prior_;
  ClosedLoopPlant& loop_;
  const ClosedLoopAdaptiveOptions& o_;
  SegmentSources sources_;
  IdentifyOptions identify_;
  std::uint32_t rows_ = 0;
  long long max_rows_ = 0;
  Eigen::VectorXd amplitude_;  // a_j
  Eigen::MatrixXd R_;          // r so far, rows × CVs
  AdaptiveResult result_;
};

}  // namespace

AdaptiveResult run_closed_loop_adaptive_test(const PriorKnowledge& prior, ClosedLoopPlant& loop,
                                             const ClosedLoopAdaptiveOptions& options) {
  return ClosedLoopTest(prior, loop, options).run();
}

}  // namespace excite::host
