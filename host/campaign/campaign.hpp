// SPDX-License-Identifier: MIT
#pragma once
// The chapter-6 study on any plant (SPEC §4–§6): a step test whose identified G(0) gives
// the directions (or the true G(0) when asked), then every preset of Table 6.1 designed,
// simulated with measurement noise, identified, judged for output balance, and every model
// cross-validated on every other experiment's data.

#include <Eigen/Core>

#include <functional>
#include <string>
#include <vector>

#include "host/identify/identify.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {

struct CampaignOptions {
  std::string plant;
  double noise_variance = -1.0;  // per output; < 0: the case study's (0.03 in thesis 6.3)
  std::uint64_t seed = 1;        // experiment e uses seed + e
  bool true_gain = false;        // directions from the true G(0) instead of the step test's
  int threads = 2;               // identification threads
};

struct Experiment {
  int number = 0;    // Table 6.1
  std::string name;  // acronym
  double sample_time_min = 0.0;
  Eigen::MatrixXd U, Y;  // N × n inputs, N × p noisy outputs (deviations)
  double cf_avg = 0.0, pips_avg = 0.0;
  IdentificationResult identified;
  double fit_avg = 0.0;  // own data, averaged over outputs (5.5.1)
  double crossfit_avg = 0.0, crossfit_best = 0.0, crossfit_worst = 0.0;
  Eigen::VectorXd projection_std;  // of w_iᵀ y, true directions (5.5.2)
  double ratio = 0.0;              // min/max of projection_std
  double upsilon = 0.0;            // det(corr(Y)) (6.2.1)
};

struct CampaignResult {
  std::string plant;
  std::vector<std::string> input_names, output_names;
  GainAnalysis true_gain;
  GainAnalysis design_gain;        // what the directional designs used
  std::string design_gain_source;  // "step test (stepSeq)" or "true G(0)"
  std::vector<Experiment> experiments;
  Eigen::MatrixXd crossfit;  // fit(a, b): model a on data b, averaged over outputs
};

/// Runs the campaign; `progress` (may be empty) gets one line per step for the terminal.
/// Throws std::invalid_argument for an unknown plant or a plant without a case study.
CampaignResult run_campaign(const CampaignOptions& options,
                            const std::function<void(const std::string&)>& progress);

}  // namespace excite::host
