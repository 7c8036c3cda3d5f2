// SPDX-License-Identifier: MIT
#pragma once
// Validation of identified models on data (SPEC §6): the fit percentage (5.5.1) and the
// cross-validation of every model on every other experiment.

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "host/identify/model.hpp"

namespace excite::host {

/// (5.5.1): 100 (1 − ‖ŷ − y‖ / ‖y − ȳ‖), percent; NaN when y is constant or ŷ has NaN.
/// Throws std::invalid_argument when the lengths differ or are zero.
double fit_percent(const Eigen::VectorXd& y, const Eigen::VectorXd& y_hat);

/// Fit % of the model on data (U: N × n, Y: N × p), one value per output. NaN for an output
/// whose row has an element that was not estimated while its input moves in U.
/// Throws std::invalid_argument on size mismatch (naming the sizes) or non-finite data.
std::vector<double> fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                        const Eigen::MatrixXd& Y);

/// An experiment's data.
struct Dataset {
  std::string name;
  Eigen::MatrixXd U;  // N × n
  Eigen::MatrixXd Y;  // N × p
};

/// Cross-validation (SPEC §6). models[a] was identified from data[a].
struct CrossValidation {
  /// fit(a, b): fit % of model a on data b, averaged over the outputs.
  Eigen::MatrixXd fit;
  struct PerModel {
    double own = 0.0;            // fit(a, a)
    double cross_average = 0.0;  // mean of fit(a, b) over b ≠ a
    double cross_best = 0.0;     // max over b ≠ a
    double cross_worst = 0.0;    // min over b ≠ a
    int best_on = -1;            // the b of cross_best
    int worst_on = -1;           // the b of cross_worst
  };
  std::vector<PerModel> models;
};

/// Every model on every data set. Needs at least two runs; all with the same n, p and
/// sample time. NaN fits (see fit()) propagate into the averages of that model.
/// Throws std::invalid_argument naming the offending run.
CrossValidation cross_validate(const std::vector<IdentifiedModel>& models,
                               const std::vector<Dataset>& data);

}  // namespace excite::host
