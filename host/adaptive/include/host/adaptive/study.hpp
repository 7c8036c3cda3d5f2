// SPDX-License-Identifier: MIT
#pragma once
// The adaptive test measured over noise seeds (issue 26 §4), in-process, against the truth
// the test itself never sees: per seed, the adaptive test on the library plant (or its
// perturbation, sim/library/perturb.hpp) with the seed's measurement noise; every
// re-estimate's G(0) judged by the Monte Carlo accuracy criterion (host/measures/
// accuracy.hpp) against the seed's true plant; the CVs' noise-free excursions against the
// test limits.
//
// Two test lengths, both on the grid of re-estimates (multiples of the segment length H):
//   - T90 (stop): the shortest length L by which ≥ 90 % of seeds have *stopped by their own
//     rule with a model that meets the criterion* — what an engineer gets, the stop decision
//     included. Monotone in L by construction (a stop is final).
//   - T90 (oracle): the shortest L from which on ≥ 90 % of seeds' latest model (the one in
//     force at L, the stopping one after a stop) meets the criterion — the Monte Carlo's own
//     definition (summary.hpp t90_index), which judges fixed designs on prefixes with the
//     truth in hand; the like-for-like comparison with their T90.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/adaptive/adaptive_test.hpp"
#include "host/simulate/closed_loop_speed.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// A study with the controller on (closed_loop_adaptive.hpp): every seed's test superimposed
/// on the CV setpoints of the file's controller, built on the file's model (a DMC refuses a
/// seed's perturbed plant whose G(0) its model does not control integrally: that seed is
/// counted as a test that did not stop, the reason kept).
struct ClosedLoopStudyOptions {
  std::string controller;         // the controller file (sim/control/README.md)
  double limit_fraction = 0.5;    // r at this share of each CV's test limit
  double mv_fraction = 1.0;       // r cut until Ĝ(0)⁻¹ r fits this share of the MVs' limits
  bool two_stage = false;         // the estimate: direct (false) or two-stage
  bool prior_directions = false;  // segment 0 along the prior's output directions
  bool switch_from_loop = true;   // (4.2.3)'s τ_L: the loop's (StudyResult) or the plant's
  std::uint64_t prbs_phase = 0;   // the PRBS started this many switching intervals in
  double disturbance_std = 0.0;   // the coloured output disturbance (host/simulate)
  double disturbance_tau_min = 0.0;
};

struct StudyOptions {
  std::string plant;  // a case-study plant (its prior knowledge is the test's)
  int seeds = 100;
  std::uint64_t first_seed = 1;
  int threads = 1;
  double noise_variance = -1.0;  // < 0: the case study's
  double perturb_percent = 0.0;  // > 0: every seed on its own perturbed linear plant
  AdaptiveOptions adaptive;      // identify.threads is set to 1 (seeds run in parallel)
  std::optional<ClosedLoopStudyOptions> closed_loop;  // the controller on (adaptive.limits
                                                      // required)
};

/// What one seed's test did, judged against its truth.
struct SeedOutcome {
  std::uint64_t seed = 0;
  bool not_run = false;  // the controller refused the seed's plant (closed loop; stop_reason
                         // says why): left out of the shares, counted apart
  bool stopped_by_rule = false;
  double stop_min = 0.0;  // the test's length
  std::string stop_reason;
  std::vector<double> estimate_min;           // each re-estimate's length
  std::vector<bool> estimate_met;             // its G(0) meets the criterion against the truth
  std::vector<double> estimate_need;          // its stop-rule need (confidence.hpp)
  std::vector<std::string> estimate_missing;  // what kept the rule from holding ("" when met)
  double true_sigma_n = 0.0;           // σ_n of the seed's true G(0) (its perturbed plant's with
                                       // perturb_percent): the weak direction the test had to find
  bool met_at_stop = false;            // the last estimate's verdict (false: none)
  double sigma_n_error_at_stop = 0.0;  // signed, relative; NaN without a G(0)
  double angle_at_stop_deg = 0.0;      // ∠(v̂_n, ±v_n); NaN without a G(0)
  int segments = 0;
  int directional_segments = 0;
  double smallest_scale = 1.0;    // of the segments amplitude control sized
  double peak_limit_ratio = 0.0;  // max over CVs and rows of dy_true / its limit on
                                  // that side (≤ 1 inside); 0 without limits
  bool violated = false;          // peak_limit_ratio > 1
};

struct StudyResult {
  StudyOptions options;
  int not_run = 0;           // seeds the controller refused (closed loop)
  double segment_min = 0.0;  // H as run (whole bits)
  double tau_low_min = 0.0;  // (4.2.3)'s τ_L of the segments' PRBS: the case study's, or with
                             // the controller on loop_speed's within [the case study's, τ_H]
  std::optional<ClosedLoopSpeed> loop_speed;  // the controller on: at_the_loops_pace's
  double switch_time_min = 0.0;               // the PRBS's T_sw from τ_L by (4.2.3)
  std::vector<double> grid_min;               // H, 2H, …, the longest test
  std::vector<double> share_stopped_met;      // per grid length: stopped by the rule with a good
                                              // model, a share of the seeds run
  std::vector<double> share_met;              // per grid length: the model in force meets it
  std::optional<std::size_t> t90_stop, t90_oracle;  // index into grid_min
  std::vector<SeedOutcome> seeds;
};

/// The seed's true plant: the library plant by name, or (perturb_percent > 0) its
/// perturbation drawn from the seed (sim/library/perturb.hpp; linear plants only, else
/// std::invalid_argument).
std::unique_ptr<sim::Plant> true_plant(const std::string& plant, double perturb_percent,
                                       std::uint64_t seed);

/// Runs the study (seeds in parallel on options.threads; the result does not depend on the
/// thread count). Throws std::invalid_argument for a plant without a case study, bad counts,
/// or a perturbation of a plant that has no linear model.
StudyResult run_study(const StudyOptions& options);

/// The peak of each CV's noise-free excursion over a fixed design's run, as a ratio to its
/// limit on that side (max over CVs; > 1: the design leaves the limits): the fixed designs
/// at their designed amplitude, for the violation comparison of issue 26 §2.
double fixed_design_peak_ratio(const std::string& plant, const std::string& design,
                               const CvLimits& limits, double perturb_percent, std::uint64_t seed);

}  // namespace excite::host
