// SPDX-License-Identifier: MIT
#include "host/measures/cross_fit.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace excite::host {

CrossFitFigures cross_fit_figures(const Eigen::Ref<const Eigen::VectorXd>& fit_row,
                                  const Eigen::Ref<const Eigen::VectorXd>& truth,
                                  Eigen::Index own) {
  const Eigen::Index R = fit_row.size();
  if (R < 2) {
    throw std::invalid_argument("cross-fit runs = " + std::to_string(R) +
                                ", expected at least 2 (a model's own run and another)");
  }
  if (own < 0 || own >= R) {
    throw std::invalid_argument("cross-fit own run = " + std::to_string(own) + ", expected 0 … " +
                                std::to_string(R - 1));
  }
  if (truth.size() != 0 && truth.size() != R) {
    throw std::invalid_argument("cross-fit truth runs = " + std::to_string(truth.size()) +
                                ", expected 0 (no truth) or " + std::to_string(R));
  }
  CrossFitFigures f;
  double sum = 0.0;
  Eigen::Index best_on = -1, worst_on = -1;
  for (Eigen::Index b = 0; b < R; ++b) {
    if (b == own) continue;
    const double v = fit_row(b);
    if (std::isnan(v)) return f;
    sum += v;
    if (best_on < 0 || v > fit_row(best_on)) best_on = b;
    if (worst_on < 0 || v < fit_row(worst_on)) worst_on = b;
  }
  f.average = sum / static_cast<double>(R - 1);
  f.best = fit_row(best_on);
  f.worst = fit_row(worst_on);
  f.best_on = best_on;
  f.worst_on = worst_on;
  if (truth.size() == 0) return f;
  f.truth_on_worst = truth(worst_on);
  double loss_sum = 0.0;
  Eigen::Index loss_worst_on = -1;
  double loss_worst = 0.0;
  for (Eigen::Index b = 0; b < R; ++b) {
    if (b == own) continue;
    const double loss = truth(b) - fit_row(b);
    if (std::isnan(loss)) return f;
    loss_sum += loss;
    if (loss_worst_on < 0 || loss > loss_worst) {
      loss_worst = loss;
      loss_worst_on = b;
    }
  }
  f.loss_average = loss_sum / static_cast<double>(R - 1);
  f.loss_worst = loss_worst;
  f.loss_worst_on = loss_worst_on;
  return f;
}

}  // namespace excite::host
