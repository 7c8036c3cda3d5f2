// SPDX-License-Identifier: MIT
#include "host/identify/model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

namespace excite::host {

const char* to_string(ElementStatus status) {
  switch (status) {
    case ElementStatus::identified:
      return "identified";
    case ElementStatus::weak_gain:
      return "weak_gain";
    case ElementStatus::input_not_moved:
      return "input_not_moved";
    case ElementStatus::input_collinear:
      return "input_collinear";
    case ElementStatus::output_not_moved:
      return "output_not_moved";
  }
  return "unknown";
}

const char* to_string(Grade grade) {
  switch (grade) {
    case Grade::A:
      return "A";
    case Grade::B:
      return "B";
    case Grade::C:
      return "C";
    case Grade::D:
      return "D";
  }
  return "?";
}

std::vector<std::string> ElementEstimate::on_bound() const {
  std::vector<std::string> out;
  for (int k = 0; k < kParameters; ++k) {
    const Bound b = at_bound[static_cast<std::size_t>(k)];
    if (b == Bound::none) continue;
    const double v = value[k];
    const bool lower = b == Bound::lower;
    char text[96];
    std::snprintf(text, sizeof text, "%s = %.4g (%s bound)",
                  parameter_name(static_cast<Parameter>(k)), v, lower ? "lower" : "upper");
    out.emplace_back(text);
  }
  return out;
}

bool ElementEstimate::on_upper_bound() const {
  for (const int k : {kDelay, kTp1, kTp2, kNatural}) {
    if (at_bound[static_cast<std::size_t>(k)] == Bound::upper) return true;
  }
  return at_bound[kZero] != Bound::none;  // |T_z| on its bound, either sign
}

GainBounds gain_interval_95(const ElementEstimate& e) {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  if (!e.estimated()) return {kNaN, kNaN};
  const double K = e.value.gain;
  const double half = 1.96 * e.std_error.gain;
  GainBounds out{kNaN, kNaN};
  if (std::isfinite(half)) out = {K - half, K + half};
  if (e.projected_gain) {
    const GainBounds& p = e.projected_gain->bounds;
    out.lower = std::isfinite(out.lower) ? std::min(out.lower, p.lower) : p.lower;
    out.upper = std::isfinite(out.upper) ? std::max(out.upper, p.upper) : p.upper;
  }
  return out;
}

Eigen::MatrixXd IdentifiedModel::static_gain() const {
  Eigen::MatrixXd G(outputs, inputs);
  for (int j = 0; j < outputs; ++j) {
    for (int i = 0; i < inputs; ++i) {
      const ElementEstimate& e = element(j, i);
      G(j, i) = e.estimated() ? e.value.static_gain() : std::numeric_limits<double>::quiet_NaN();
    }
  }
  return G;
}

Eigen::MatrixXd simulate(const IdentifiedModel& model, const Eigen::MatrixXd& U) {
  if (U.cols() != model.inputs) {
    throw std::invalid_argument("simulate: U has " + std::to_string(U.cols()) +
                                " columns (inputs) but the model has " +
                                std::to_string(model.inputs));
  }
  const auto N = static_cast<std::size_t>(U.rows());
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(U.rows(), model.outputs);
  Eigen::VectorXd z(U.rows());
  for (int j = 0; j < model.outputs; ++j) {
    for (int i = 0; i < model.inputs; ++i) {
      const ElementEstimate& e = model.element(j, i);
      if (e.estimated()) {
        simulate(discretise(e.value, model.sample_time_min), {U.col(i).data(), N}, {z.data(), N});
        Y.col(j) += z;
      } else if (U.col(i).cwiseAbs().maxCoeff() > 0.0) {
        Y.col(j).setConstant(std::numeric_limits<double>::quiet_NaN());
      }
    }
  }
  return Y;
}

}  // namespace excite::host
