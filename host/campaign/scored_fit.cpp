// SPDX-License-Identifier: MIT
#include "host/campaign/scored_fit.hpp"

#include <cmath>
#include <limits>

#include "host/identify/validate.hpp"

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool one_whole_segment(const SampleLayout& layout) {
  return layout.segments.size() == 1 && layout.scored() == layout.rows();
}

// Y_hat from `simulate_segment(U rows)` over each segment, from rest at its start.
template <typename Simulate>
Eigen::MatrixXd per_segment(const Eigen::MatrixXd& U, Eigen::Index outputs,
                            const SampleLayout& layout, Simulate simulate_segment) {
  Eigen::MatrixXd Y_hat = Eigen::MatrixXd::Zero(U.rows(), outputs);
  for (const Segment& s : layout.segments) {
    Y_hat.middleRows(s.begin, s.end - s.begin) =
        simulate_segment(U.middleRows(s.begin, s.end - s.begin));
  }
  return Y_hat;
}

}  // namespace

double mean_scored_fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                       const Eigen::MatrixXd& Y, const SampleLayout& layout) {
  const std::vector<double> f = scored_fit(model, U, Y, layout);
  double sum = 0.0;
  for (const double v : f) sum += v;
  return sum / static_cast<double>(f.size());
}

double mean_finite(const std::vector<double>& v) {
  double sum = 0.0;
  int n = 0;
  for (const double x : v) {
    if (std::isfinite(x)) {
      sum += x;
      ++n;
    }
  }
  return n > 0 ? sum / n : kNaN;
}

std::vector<double> scored_fit_of(const Eigen::MatrixXd& Y_hat, const Eigen::MatrixXd& Y,
                                  const SampleLayout& layout) {
  std::vector<double> out;
  if (one_whole_segment(layout)) {
    for (Eigen::Index j = 0; j < Y.cols(); ++j) out.push_back(fit_percent(Y.col(j), Y_hat.col(j)));
    return out;
  }
  const Eigen::MatrixXd y = layout.scored_rows(Y, 0, Y.rows());
  const Eigen::MatrixXd y_hat = layout.scored_rows(Y_hat, 0, Y.rows());
  for (Eigen::Index j = 0; j < Y.cols(); ++j) {
    out.push_back(y.rows() > 0 ? fit_percent(y.col(j), y_hat.col(j)) : kNaN);
  }
  return out;
}

std::vector<double> scored_fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                               const Eigen::MatrixXd& Y, const SampleLayout& layout) {
  if (one_whole_segment(layout)) return fit(model, U, Y);
  return scored_fit_of(per_segment(U, model.outputs, layout,
                                   [&](const Eigen::MatrixXd& u) { return simulate(model, u); }),
                       Y, layout);
}

std::vector<double> truth_fit(sim::Plant& plant, const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y,
                              double sample_time_min, const SampleLayout& layout) {
  return scored_fit_of(
      per_segment(U, Y.cols(), layout,
                  [&](const Eigen::MatrixXd& u) { return plant.simulate(u, sample_time_min); }),
      Y, layout);
}

}  // namespace excite::host
