// SPDX-License-Identifier: MIT
#pragma once
// Integral controllability of a controller's model against the plant it controls: a
// controller with integral action built on a model G_m keeps the loop stable at low
// frequency only when every principal minor of G_m(0) has the sign of the plant's (Morari
// 1985; Koung and MacGregor 1993) — the sense of host/identify's gain uncertainty and
// host/montecarlo's accuracy criterion, computed here because sim does not use host.
// An ill-conditioned plant's det G(0) is the minor a ±10 % model error flips first.

#include <Eigen/Dense>

#include <string_view>
#include <vector>

#include "base/config/check.hpp"

namespace excite::sim::control {

/// det G[S,S] for every non-empty index set S of a square G, S ordered by its bit mask
/// (1, 2, 3, …): 2^n − 1 values. std::invalid_argument when G is not square or n > 16.
std::vector<double> principal_minors(const Eigen::MatrixXd& gain);

/// ok, or a failed check (field "model") naming the first principal minor whose sign the
/// model gets wrong, its value and the plant's. Minors the plant has at exactly 0 are not
/// compared. Non-square gains are not checked (ok).
config::Check check_integral_controllability(const Eigen::MatrixXd& model_gain,
                                             const Eigen::MatrixXd& plant_gain,
                                             std::string_view model_name);

}  // namespace excite::sim::control
