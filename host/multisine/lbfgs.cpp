// SPDX-License-Identifier: MIT
#include "host/multisine/lbfgs.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace excite::host::multisine {

LbfgsResult lbfgs_minimise(const Objective& f, Eigen::VectorXd& x, const LbfgsOptions& options) {
  const Eigen::Index n = x.size();
  const auto memory = static_cast<std::size_t>(std::max(options.memory, 1));
  std::vector<Eigen::VectorXd> s_history;
  std::vector<Eigen::VectorXd> y_history;
  std::vector<double> rho_history;
  std::vector<double> alpha(memory);

  LbfgsResult result;
  Eigen::VectorXd gradient(n);
  double value = f(x, gradient);
  ++result.evaluations;

  Eigen::VectorXd direction(n);
  Eigen::VectorXd trial(n);
  Eigen::VectorXd trial_gradient(n);
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (gradient.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) break;

    // Two-loop recursion: direction = −H·∇f.
    direction = -gradient;
    const std::size_t stored = s_history.size();
    for (std::size_t k = stored; k-- > 0;) {
      alpha[k] = rho_history[k] * s_history[k].dot(direction);
      direction -= alpha[k] * y_history[k];
    }
    double step = 1.0;
    if (stored > 0) {
      const double gamma = s_history.back().dot(y_history.back()) / y_history.back().squaredNorm();
      direction *= gamma;
    } else {
      step = options.max_first_step / std::max(direction.lpNorm<Eigen::Infinity>(), 1e-300);
    }
    for (std::size_t k = 0; k < stored; ++k) {
      const double beta = rho_history[k] * y_history[k].dot(direction);
      direction += (alpha[k] - beta) * s_history[k];
    }
    double slope = gradient.dot(direction);
    if (slope >= 0.0) {  // not a descent direction: restart from steepest descent
      s_history.clear();
      y_history.clear();
      rho_history.clear();
      direction = -gradient;
      slope = gradient.dot(direction);
      step = options.max_first_step / std::max(direction.lpNorm<Eigen::Infinity>(), 1e-300);
    }

    // Backtracking Armijo line search.
    constexpr double kArmijo = 1e-4;
    bool accepted = false;
    double trial_value = value;
    for (int halving = 0; halving < 30; ++halving) {
      trial = x + step * direction;
      trial_value = f(trial, trial_gradient);
      ++result.evaluations;
      if (std::isfinite(trial_value) && trial_value <= value + kArmijo * step * slope) {
        accepted = true;
        break;
      }
      step *= 0.5;
    }
    if (!accepted) break;

    Eigen::VectorXd s = trial - x;
    Eigen::VectorXd y = trial_gradient - gradient;
    const double sy = s.dot(y);
    if (sy > 1e-12 * s.norm() * y.norm()) {
      if (s_history.size() == memory) {
        s_history.erase(s_history.begin());
        y_history.erase(y_history.begin());
        rho_history.erase(rho_history.begin());
      }
      s_history.push_back(std::move(s));
      y_history.push_back(std::move(y));
      rho_history.push_back(1.0 / sy);
    }
    const double decrease = value - trial_value;
    x = trial;
    gradient = trial_gradient;
    value = trial_value;
    result.iterations = iteration + 1;
    if (decrease <= options.relative_decrease * std::abs(value)) break;
  }
  result.value = value;
  return result;
}

}  // namespace excite::host::multisine
