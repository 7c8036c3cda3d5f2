// SPDX-License-Identifier: MIT
#include "host/multisine/lbfgs.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace excite::host::multisine {

namespace {

// The last `memory` curvature pairs (s, y), oldest first, with ρ = 1/(sᵀy).
class CurvatureHistory {
 public:
  explicit CurvatureHistory(std::size_t memory) : memory_(memory), alpha_(memory) {}

  bool empty() const { return s_.empty(); }

  void clear() {
    s_.clear();
    y_.clear();
    rho_.clear();
  }

  // d = −H·∇f by the two-loop recursion, H scaled by γ = sᵀy / yᵀy of the newest pair;
  // −∇f when no pair is stored.
  void direction(const Eigen::VectorXd& gradient, Eigen::VectorXd& d) {
    d = -gradient;
    const std::size_t stored = s_.size();
    for (std::size_t k = stored; k-- > 0;) {
      alpha_[k] = rho_[k] * s_[k].dot(d);
      d -= alpha_[k] * y_[k];
    }
    if (stored > 0) {
      const double gamma = s_.back().dot(y_.back()) / y_.back().squaredNorm();
      d *= gamma;
    }
    for (std::size_t k = 0; k < stored; ++k) {
      const double beta = rho_[k] * y_[k].dot(d);
      d += (alpha_[k] - beta) * s_[k];
    }
  }

  // Keeps the pair when its curvature sᵀy is positive (beyond rounding), dropping the oldest
  // when full.
  void remember(Eigen::VectorXd s, Eigen::VectorXd y) {
    const double sy = s.dot(y);
    if (!(sy > 1e-12 * s.norm() * y.norm())) return;
    if (s_.size() == memory_) {
      s_.erase(s_.begin());
      y_.erase(y_.begin());
      rho_.erase(rho_.begin());
    }
    s_.push_back(std::move(s));
    y_.push_back(std::move(y));
    rho_.push_back(1.0 / sy);
  }

 private:
  std::size_t memory_;
  std::vector<Eigen::VectorXd> s_;
  std::vector<Eigen::VectorXd> y_;
  std::vector<double> rho_;
  std::vector<double> alpha_;
};

}  // namespace

LbfgsResult lbfgs_minimise(const Objective& f, Eigen::VectorXd& x, const LbfgsOptions& options) {
  const Eigen::Index n = x.size();
  CurvatureHistory history(static_cast<std::size_t>(std::max(options.memory, 1)));

  LbfgsResult result;
  Eigen::VectorXd gradient(n);
  double value = f(x, gradient);
  ++result.evaluations;

  Eigen::VectorXd direction(n);
  Eigen::VectorXd trial(n);
  Eigen::VectorXd trial_gradient(n);
  // The first step of a steepest-descent direction: at most max_first_step in any coordinate.
  const auto first_step = [&] {
    return options.max_first_step / std::max(direction.lpNorm<Eigen::Infinity>(), 1e-300);
  };
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (gradient.lpNorm<Eigen::Infinity>() < options.gradient_tolerance) break;

    const bool steepest = history.empty();
    history.direction(gradient, direction);
    double step = steepest ? first_step() : 1.0;
    double slope = gradient.dot(direction);
    if (slope >= 0.0) {  // not a descent direction: restart from steepest descent
      history.clear();
      direction = -gradient;
      slope = gradient.dot(direction);
      step = first_step();
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

    history.remember(trial - x, trial_gradient - gradient);
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
