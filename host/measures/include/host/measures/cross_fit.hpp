// SPDX-License-Identifier: MIT
#pragma once
// One model's cross-validation figures (SPEC §6) and, where the truth is known, its loss
// against the truth (issue 45).
//
// A cross-fit fit(a, b) (5.5.1: model a on run b, averaged over outputs) is bounded by run
// b's noise: no model, the true one included, predicts the noise, so on a noisy run every
// good model reaches about the same fit and the worst cross-fit names the noisiest run,
// not the worst model. On a simulated run the true plant's fit truth(b) (same rows, same
// rule) is that bound, and
//
//   loss(a, b) = truth(b) − fit(a, b)   [points of fit %]
//
// is what model a loses through being wrong, whatever the run's noise. With measured data
// (no truth) `worst_on` still says which run bounds the worst cross-fit.

#include <Eigen/Core>

#include <limits>

namespace excite::host {

struct CrossFitFigures {
  static constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  double average = kNaN;                     // mean of fit(a, b) over b ≠ a, %
  double best = kNaN;                        // max over b ≠ a, %
  double worst = kNaN;                       // min over b ≠ a, %
  Eigen::Index best_on = -1, worst_on = -1;  // the run b of best and worst; -1 when NaN
  double truth_on_worst = kNaN;              // truth(worst_on), %; NaN without truth
  double loss_average = kNaN;                // mean of loss(a, b) over b ≠ a, points
  double loss_worst = kNaN;                  // max of loss(a, b) over b ≠ a, points
  Eigen::Index loss_worst_on = -1;           // the run b of loss_worst; -1 when NaN
};

/// Model `own`'s figures over the other runs: fit_row(b) = fit(own, b) in %, truth(b) the
/// true plant's fit on run b in % (empty: no truth known; then the loss fields stay NaN).
/// A NaN fit(own, b) makes every figure NaN (a model that cannot predict one run has no
/// cross-fit); a NaN truth(b) makes the loss figures NaN. Averages are the plain sums over b
/// in order divided by R − 1. Throws std::invalid_argument when `own` is outside the row, the
/// row has fewer than two runs, or truth is neither empty nor as long as the row.
CrossFitFigures cross_fit_figures(const Eigen::Ref<const Eigen::VectorXd>& fit_row,
                                  const Eigen::Ref<const Eigen::VectorXd>& truth, Eigen::Index own);

}  // namespace excite::host
