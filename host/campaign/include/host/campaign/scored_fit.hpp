// SPDX-License-Identifier: MIT
#pragma once
// How the campaign scores a prediction of a run (5.5.1, SPEC §6): the predictor simulated
// from rest at each of the run's segments, fit % per output over the rows the run's layout
// scores (host/identify/segments.hpp). The same rule for an identified model (the
// cross-fit) and for the true plant (the bound the run's noise sets, host/measures/
// cross_fit.hpp), so that their difference is the model's loss and nothing else.

#include <Eigen/Core>

#include <vector>

#include "host/identify/model.hpp"
#include "host/identify/segments.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// Fit % of `model` on U (N × n), Y (N × p) per output; one segment scoring every row gives
/// fit() (host/identify/validate.hpp), NaN where it does.
std::vector<double> scored_fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                               const Eigen::MatrixXd& Y, const SampleLayout& layout);

/// scored_fit averaged over the outputs; a NaN output fit makes it NaN (a model that cannot
/// predict one output of a run has no fit on it: the cross-validation's rule, SPEC §6).
double mean_scored_fit(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                       const Eigen::MatrixXd& Y, const SampleLayout& layout);

/// Fit % per output of a prediction Y_hat (N × p, already from rest at each segment) of Y.
std::vector<double> scored_fit_of(const Eigen::MatrixXd& Y_hat, const Eigen::MatrixXd& Y,
                                  const SampleLayout& layout);

/// The true plant's fit % per output on U, Y: `plant` simulated (sim::Plant::simulate, no
/// noise) from rest at each segment's start, sampled every sample_time_min minutes.
std::vector<double> truth_fit(sim::Plant& plant, const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y,
                              double sample_time_min, const SampleLayout& layout);

/// The mean of the finite entries; NaN when there is none.
double mean_finite(const std::vector<double>& v);

}  // namespace excite::host
