// SPDX-License-Identifier: MIT
#include "sim/control/step_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"

namespace excite::sim::control {

const Eigen::MatrixXd& StepModel::at(int k) const {
  return coefficients[static_cast<std::size_t>(std::clamp(k, 0, horizon()))];
}

StepModel StepModel::delayed(int samples) const {
  if (samples < 0) {
    throw std::invalid_argument("delay_samples = " + std::to_string(samples) +
                                ", expected a whole number of samples >= 0");
  }
  StepModel out = *this;
  out.coefficients.insert(out.coefficients.begin(), static_cast<std::size_t>(samples),
                          Eigen::MatrixXd::Zero(outputs, inputs));
  return out;
}

StepModel step_model(Plant& model, double sample_time_min, const StepModelOptions& options) {
  if (!(std::isfinite(sample_time_min) && sample_time_min > 0.0)) {
    throw std::invalid_argument("sample_time_min = " + config::format_number(sample_time_min) +
                                ", expected a finite number of minutes > 0");
  }
  if (!(std::isfinite(options.probe_step) && options.probe_step > 0.0)) {
    throw std::invalid_argument("probe_step = " + config::format_number(options.probe_step) +
                                ", expected a finite MV step > 0");
  }
  const int n = model.inputs();
  const int p = model.outputs();
  int length = 512;
  while (true) {
    // One probe per MV; row k of the response is sampled at kT.
    std::vector<Eigen::MatrixXd> responses;
    int settled = 1;  // the first sample from which every response is final
    bool within_window = true;
    for (int j = 0; j < n; ++j) {
      Eigen::MatrixXd du = Eigen::MatrixXd::Zero(length, n);
      du.col(j).setConstant(options.probe_step);
      Eigen::MatrixXd y = model.simulate(du, sample_time_min) / options.probe_step;
      const Eigen::VectorXd final_value = y.row(length - 1).transpose();
      const double scale = std::max(y.cwiseAbs().maxCoeff(), 1e-300);
      int last_off = 0;
      for (int k = 0; k < length; ++k) {
        if ((y.row(k).transpose() - final_value).cwiseAbs().maxCoeff() >
            options.settle_tolerance * scale) {
          last_off = k;
        }
      }
      // Settled only if the last half of the window is flat (a slow drift is not final).
      const int half = length / 2;
      const double drift = (y.row(length - 1) - y.row(half)).cwiseAbs().maxCoeff();
      if (last_off >= half || drift > 0.1 * options.settle_tolerance * scale) within_window = false;
      settled = std::max(settled, last_off + 1);
      responses.push_back(std::move(y));
    }
    if (within_window) {
      StepModel out;
      out.sample_time_min = sample_time_min;
      out.inputs = n;
      out.outputs = p;
      out.coefficients.assign(static_cast<std::size_t>(settled) + 1, Eigen::MatrixXd::Zero(p, n));
      for (int k = 0; k <= settled; ++k) {
        for (int j = 0; j < n; ++j) {
          out.coefficients[static_cast<std::size_t>(k)].col(j) =
              responses[static_cast<std::size_t>(j)].row(k).transpose();
        }
      }
      // The truncated tail is the final value itself, so S_N = G(0) of the response.
      for (int j = 0; j < n; ++j) {
        out.coefficients.back().col(j) =
            responses[static_cast<std::size_t>(j)].row(length - 1).transpose();
      }
      return out;
    }
    if (length >= options.max_horizon) {
      throw std::invalid_argument(
          "model = \"" + model.name() + "\" (step responses not settled after " +
          std::to_string(length) + " samples of " + config::format_number(sample_time_min) +
          " min), expected a model whose every step response settles (DMC's truncated step "
          "model: no integrator, no unstable element)");
    }
    length *= 2;
  }
}

}  // namespace excite::sim::control
