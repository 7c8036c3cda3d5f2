// SPDX-License-Identifier: MIT
#pragma once
// The step-response model of DMC (Cutler and Ramaker 1980): S_k, the p × n matrix of the
// CVs' responses at sample k to unit steps of each MV applied from sample 0 (S_0 = 0: an
// MV moved at kT reaches the CVs from (k+1)T at the earliest), truncated at the settling
// horizon N: S_k = S_N for k ≥ N. Deviation variables, the plant's units per unit MV;
// sample time T minutes.

#include <Eigen/Dense>

#include <vector>

#include "sim/plants/plant.hpp"

namespace excite::sim::control {

struct StepModel {
  double sample_time_min = 1.0;
  int inputs = 0;   // n
  int outputs = 0;  // p
  // coefficients[k] = S_k for k = 0 … N (N = horizon()); S_0 = 0.
  std::vector<Eigen::MatrixXd> coefficients;

  int horizon() const { return static_cast<int>(coefficients.size()) - 1; }
  /// S_k, S_N beyond the horizon.
  const Eigen::MatrixXd& at(int k) const;
  /// G(0) of the truncated model: S_N.
  const Eigen::MatrixXd& gain() const { return coefficients.back(); }
  /// The same model with `samples` more dead time on every element (S'_k = S_{k−samples}):
  /// the loop's own delay between reading y and applying u.
  StepModel delayed(int samples) const;
};

/// How a plant's step responses are taken and where they are cut.
struct StepModelOptions {
  double probe_step = 1.0;         // MV step of each probe; S = response / probe_step
  double settle_tolerance = 1e-3;  // settled: every |S_k − S_final| ≤ this · max |S| per MV
  int max_horizon = 1 << 15;       // samples; a model not settled by then is refused
};

/// Step responses of `model` (deviations from its operating point) at T minutes, one
/// simulate() per MV, cut at the first sample after which every response stays within the
/// tolerance of its final value. Throws std::invalid_argument naming sample_time_min,
/// probe_step or the model (one that does not settle: an integrator, an unstable element).
StepModel step_model(Plant& model, double sample_time_min, const StepModelOptions& options = {});

}  // namespace excite::sim::control
