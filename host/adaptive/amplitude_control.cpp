// SPDX-License-Identifier: MIT
#include "host/adaptive/amplitude_control.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "host/identify/segments.hpp"

namespace excite::host {
namespace {

// Bisection steps for α: 2^-60 of max_scale, far below any meaningful amplitude.
constexpr int kBisections = 60;

[[noreturn]] void refuse(const std::string& what) {
  throw std::invalid_argument(what);
}

void check_arguments(const IdentifiedModel& model, const Eigen::MatrixXd& history,
                     const Eigen::MatrixXd& segment, const CvLimits& limits,
                     const ScaleOptions& options) {
  const auto n = static_cast<Eigen::Index>(model.inputs);
  const auto p = static_cast<Eigen::Index>(model.outputs);
  if (!(model.sample_time_min > 0.0)) {
    std::ostringstream m;
    m << "model sample time = " << model.sample_time_min << " min, expected > 0";
    refuse(m.str());
  }
  if (history.cols() != n && history.rows() > 0) {
    std::ostringstream m;
    m << "history columns = " << history.cols() << ", expected " << n << " (the model's inputs)";
    refuse(m.str());
  }
  if (segment.cols() != n || segment.rows() < 1) {
    std::ostringstream m;
    m << "segment = " << segment.rows() << " × " << segment.cols() << ", expected at least 1 row"
      << " × " << n << " (the model's inputs)";
    refuse(m.str());
  }
  if (!history.allFinite() || !segment.allFinite())
    refuse("history or segment holds a value that is not finite, expected finite deviations");
  if (limits.low.size() != p || limits.high.size() != p) {
    std::ostringstream m;
    m << "CV limits = " << limits.low.size() << " low and " << limits.high.size()
      << " high, expected " << p << " each (the model's outputs)";
    refuse(m.str());
  }
  for (Eigen::Index j = 0; j < p; ++j) {
    if (!(limits.low(j) < 0.0 && limits.high(j) > 0.0)) {
      std::ostringstream m;
      m << "output " << j + 1 << " limits = [" << limits.low(j) << ", " << limits.high(j)
        << "] (deviation from the baseline), expected low < 0 < high";
      refuse(m.str());
    }
  }
  if (!(options.k_sigma >= 0.0 && std::isfinite(options.k_sigma)) ||
      !(options.max_scale > 0.0 && std::isfinite(options.max_scale))) {
    std::ostringstream m;
    m << "k_sigma = " << options.k_sigma << ", max_scale = " << options.max_scale
      << ", expected k_sigma ≥ 0 and max_scale > 0, both finite";
    refuse(m.str());
  }
}

// The element's response to u over all of u's rows, from rest.
Eigen::VectorXd respond(const ElementModel& g, double T, const Eigen::VectorXd& u) {
  Eigen::VectorXd y(u.size());
  simulate_segments(discretise(g, T), {u.data(), static_cast<std::size_t>(u.size())},
                    {y.data(), static_cast<std::size_t>(y.size())}, {Segment{0, u.size()}});
  return y;
}

// One output's prediction on the window: y = h + α s, σ² = a + 2αb + α²c.
struct RowPrediction {
  Eigen::VectorXd h, s, a, b, c;
  std::string unknown;  // why the prediction cannot be made ("" when it can)
};

// The row's gains are correlated (one MISO fit): the covariances between its elements, on
// the unit responses of the elements whose inputs move (an empty vector: input still).
void add_gain_covariances(const IdentifiedModel& model, int j,
                          const std::vector<Eigen::VectorXd>& unit_h,
                          const std::vector<Eigen::VectorXd>& unit_s, RowPrediction& r) {
  const auto row = static_cast<std::size_t>(j);
  if (row >= model.gain_covariance.size()) return;
  const Eigen::MatrixXd& G = model.gain_covariance[row];
  for (int i = 0; i < model.inputs; ++i) {
    for (int k = 0; k < model.inputs; ++k) {
      const auto si = static_cast<std::size_t>(i), sk = static_cast<std::size_t>(k);
      if (i == k || unit_h[si].size() == 0 || unit_h[sk].size() == 0 || !std::isfinite(G(i, k)))
        continue;
      r.a += G(i, k) * unit_h[si].cwiseProduct(unit_h[sk]);
      r.b += G(i, k) * unit_h[si].cwiseProduct(unit_s[sk]);
      r.c += G(i, k) * unit_s[si].cwiseProduct(unit_s[sk]);
    }
  }
}

RowPrediction predict_row(const IdentifiedModel& model, int j, const Eigen::MatrixXd& u_history,
                          const Eigen::MatrixXd& u_segment, Eigen::Index first, Eigen::Index rows) {
  const double T = model.sample_time_min;
  RowPrediction r;
  r.h = r.s = r.a = r.b = r.c = Eigen::VectorXd::Zero(rows);
  const auto window = [&](const Eigen::VectorXd& v) { return v.segment(first, rows); };
  std::vector<Eigen::VectorXd> unit_h(static_cast<std::size_t>(model.inputs));
  std::vector<Eigen::VectorXd> unit_s(static_cast<std::size_t>(model.inputs));
  for (int i = 0; i < model.inputs; ++i) {
    const bool moves = !u_history.col(i).isZero(0.0) || !u_segment.col(i).isZero(0.0);
    if (!moves) continue;
    const ElementEstimate& e = model.element(j, i);
    if (!e.estimated()) {
      r.unknown = "element (output " + std::to_string(j + 1) + ", input " + std::to_string(i + 1) +
                  ") was not estimated and its input moves";
      return r;
    }
    ElementModel unit = e.value;
    unit.gain = 1.0;
    unit_h[static_cast<std::size_t>(i)] = window(respond(unit, T, u_history.col(i)));
    unit_s[static_cast<std::size_t>(i)] = window(respond(unit, T, u_segment.col(i)));
    r.h += e.value.gain * unit_h[static_cast<std::size_t>(i)];
    r.s += e.value.gain * unit_s[static_cast<std::size_t>(i)];
    // Sensitivities of the known-uncertain parameters (a NaN row: on its bound, known).
    std::vector<int> uncertain;
    for (const int k : free_parameters(e.value.structure)) {
      const double v = e.covariance(k, k);
      if (std::isnan(v)) continue;
      if (!std::isfinite(v)) {
        r.unknown = "element (output " + std::to_string(j + 1) + ", input " +
                    std::to_string(i + 1) + ") has a parameter the data do not determine";
        return r;
      }
      uncertain.push_back(k);
    }
    const auto q = static_cast<Eigen::Index>(uncertain.size());
    Eigen::MatrixXd dh(rows, q), ds(rows, q), C(q, q);
    for (Eigen::Index a = 0; a < q; ++a) {
      const int k = uncertain[static_cast<std::size_t>(a)];
      for (Eigen::Index b = 0; b < q; ++b)
        C(a, b) = e.covariance(k, uncertain[static_cast<std::size_t>(b)]);
      if (k == kGain) {  // the response is linear in K
        dh.col(a) = unit_h[static_cast<std::size_t>(i)];
        ds.col(a) = unit_s[static_cast<std::size_t>(i)];
        continue;
      }
      const double step = 1e-6 * std::max(std::abs(e.value[k]), k == kDamping ? 1.0 : T);
      // One-sided where the parameter's range ends: T's ≥ 0, kMinDamping ≤ ζ ≤ 1 (T_z free).
      ElementModel plus = e.value, minus = e.value;
      plus[k] = k == kDamping ? std::min(plus[k] + step, 1.0) : plus[k] + step;
      minus[k] = k == kZero      ? minus[k] - step
                 : k == kDamping ? std::max(minus[k] - step, kMinDamping)
                                 : std::max(minus[k] - step, 0.0);
      const double width = plus[k] - minus[k];
      dh.col(a) = (window(respond(plus, T, u_history.col(i))) -
                   window(respond(minus, T, u_history.col(i)))) /
                  width;
      ds.col(a) = (window(respond(plus, T, u_segment.col(i))) -
                   window(respond(minus, T, u_segment.col(i)))) /
                  width;
    }
    const Eigen::MatrixXd hC = dh * C, sC = ds * C;
    r.a += hC.cwiseProduct(dh).rowwise().sum();
    r.b += hC.cwiseProduct(ds).rowwise().sum();
    r.c += sC.cwiseProduct(ds).rowwise().sum();
  }
  add_gain_covariances(model, j, unit_h, unit_s, r);
  return r;
}

// The first (output, row) whose band leaves its limits at α; {-1, -1} when none does.
struct Violation {
  int output = -1;
  Eigen::Index row = -1;
  bool high = false;
};

Violation first_violation(const std::vector<RowPrediction>& rows, const CvLimits& limits, double k,
                          double alpha) {
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const RowPrediction& r = rows[j];
    const auto jj = static_cast<Eigen::Index>(j);
    for (Eigen::Index t = 0; t < r.h.size(); ++t) {
      const double y = r.h(t) + alpha * r.s(t);
      const double var = r.a(t) + 2.0 * alpha * r.b(t) + alpha * alpha * r.c(t);
      const double band = k * std::sqrt(std::max(var, 0.0));
      if (y + band > limits.high(jj)) return {static_cast<int>(j), t, true};
      if (y - band < limits.low(jj)) return {static_cast<int>(j), t, false};
    }
  }
  return {};
}

}  // namespace

SegmentScale scale_segment(const IdentifiedModel& model, const Eigen::MatrixXd& history,
                           const Eigen::MatrixXd& segment, const CvLimits& limits,
                           const ScaleOptions& options) {
  check_arguments(model, history, segment, limits, options);
  const Eigen::Index H = history.rows(), S = segment.rows();
  double settling = 0.0;
  for (const ElementEstimate& e : model.elements) {
    if (e.estimated()) settling = std::max(settling, settling_time_min(e.value));
  }
  const auto tail = static_cast<Eigen::Index>(std::ceil(settling / model.sample_time_min));
  const Eigen::Index L = H + S + tail;
  // The history followed by zeros, and the segment after the history's rows.
  Eigen::MatrixXd u_history = Eigen::MatrixXd::Zero(L, model.inputs);
  Eigen::MatrixXd u_segment = Eigen::MatrixXd::Zero(L, model.inputs);
  if (H > 0) u_history.topRows(H) = history;
  u_segment.middleRows(H, S) = segment;

  SegmentScale out;
  std::vector<RowPrediction> rows;
  for (int j = 0; j < model.outputs; ++j) {
    rows.push_back(predict_row(model, j, u_history, u_segment, H, S + tail));
    if (!rows.back().unknown.empty()) {
      out.reason = "no prediction: " + rows.back().unknown;
      return out;
    }
  }
  const double k = options.k_sigma;
  if (const Violation v = first_violation(rows, limits, k, 0.0); v.output >= 0) {
    out.binding_output = v.output;
    out.binding_row = v.row;
    out.binding_high = v.high;
    out.history_leaves = true;
    out.reason = "the history alone is predicted to leave output " + std::to_string(v.output + 1) +
                 "'s " + (v.high ? "high" : "low") + " limit at row " + std::to_string(v.row) +
                 " of the segment";
    return out;
  }
  if (first_violation(rows, limits, k, options.max_scale).output < 0) {
    out.scale = options.max_scale;
    return out;
  }
  double feasible = 0.0, infeasible = options.max_scale;
  for (int step = 0; step < kBisections; ++step) {
    const double mid = 0.5 * (feasible + infeasible);
    (first_violation(rows, limits, k, mid).output < 0 ? feasible : infeasible) = mid;
  }
  const Violation v = first_violation(rows, limits, k, infeasible);
  out.scale = feasible;
  out.binding_output = v.output;
  out.binding_row = v.row;
  out.binding_high = v.high;
  std::ostringstream m;
  m << "output " << v.output + 1 << "'s " << (v.high ? "high" : "low") << " limit at row " << v.row
    << " of the segment (prediction ± " << k << " σ)";
  out.reason = m.str();
  return out;
}

}  // namespace excite::host
