// SPDX-License-Identifier: MIT
#pragma once
// The chapter-6 study on any plant (SPEC §3–§6): every preset of Table 6.1 designed with
// the true G(0) (or, when asked, the step test's estimate), sized by static output,
// simulated with measurement noise, identified, judged for output balance on the
// noise-free and the noisy outputs, and every model cross-validated on every other
// experiment's data. Designs, identifications and cross-validations run on a pool of
// threads; the results do not depend on the thread count.

#include <Eigen/Core>

#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/segments.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// Which G(0) the designs use.
enum class DesignGain {
  true_gain,  // the plant's G(0) (default, thesis 6.3)
  step_test,  // identified from the sequential step test (experiment 1, thesis 6.1.1)
};

/// One experiment's measured run, as the campaign asks for it.
struct RunRequest {
  const plan::Plan& plan;
  int number = 0;               // Table 6.1
  std::string name;             // acronym
  std::uint64_t seed = 0;       // of the measurement noise
  double noise_variance = 0.0;  // per output
};

/// A measured run and which of its rows count (issue 23 §4: the campaign honours a run
/// log's flags as identify does).
struct MeasuredData {
  SimulatedRun run;
  /// The rows of `run` by the flags rule (host/identify/run_layout.hpp): where the model
  /// restarts from rest and which rows are scored. Empty (no rows): one segment, every row
  /// scored — a run simulated in this process has no flags.
  SampleLayout layout;
};

/// Makes a measured run: deviations, at least the plan's rows (rows past them, such as a
/// gateway's closing ticks at the baseline, are not part of the experiment and are dropped).
using MeasuredRun = std::function<MeasuredData(const RunRequest&)>;

struct CampaignOptions {
  std::string plant;
  double noise_variance = -1.0;  // per output; < 0: the case study's (5e-4 linear plants)
  std::uint64_t seed = 1;        // experiment e uses seed + e
  DesignGain design_gain = DesignGain::true_gain;
  int threads = 2;  // experiments and cross-validations in parallel (≥ 1)
  /// Compare designs of different lengths (refused otherwise, naming every length: SPEC §4).
  bool allow_unequal_length = false;
  /// Where the measured (noisy) runs come from: empty, simulate_plan in this process; set,
  /// the caller's — `excite campaign --loop` streams each plan through the real
  /// excite-gateway to the real excite-plant (host/loop). Called from the pool's threads.
  /// The noise-free runs that balance is measured on are always simulated here.
  MeasuredRun measured_run;
  /// The plant the runs are simulated on (the noise-free one, and the measured one unless
  /// measured_run is set): empty, sim::make_plant(plant); set, the caller's — host/montecarlo
  /// runs a seed's perturbed "true" plant while the designs keep the nominal one. Called from
  /// the pool's threads; each call gives a plant of its own.
  std::function<std::unique_ptr<sim::Plant>()> true_plant;
  /// Every element of every model in this structure (issue 45: `two_poles` is the thesis's
  /// model class, two poles and a delay, 6.1.1, in which its Tables 6.3–6.5 were drawn);
  /// nullopt: each element's structure chosen by BIC (host/identify/structure_search.hpp).
  std::optional<Structure> structure;
  /// The measured runs are runs of the plant simulated here (true_plant, else plant), so
  /// the true plant's fit on each run is known and every cross-fit is measured against it
  /// (host/measures/cross_fit.hpp). False for a measured_run from a real unit: no truth;
  /// the report still names the run that bounds each model's worst cross-fit.
  bool truth_known = true;
};

/// Output balance of one experiment's outputs (5.5.2, 6.2.1).
struct Balance {
  Eigen::VectorXd projection_std;  // of w_iᵀ y, true directions (5.5.2)
  double ratio = 0.0;              // min/max of projection_std
  double upsilon = 0.0;            // det(corr(Y)) (6.2.1)
};

/// The balance of outputs Y (N × p) along `true_gain`'s output directions (5.5.2) and their
/// correlation determinant (6.2.1).
Balance balance_of(const Eigen::MatrixXd& Y, const GainAnalysis& true_gain);

struct Experiment {
  int number = 0;    // Table 6.1
  std::string name;  // acronym
  double sample_time_min = 0.0;
  Eigen::MatrixXd U, Y;        // N × n inputs, N × p noisy outputs (deviations)
  Eigen::MatrixXd Y_clean;     // N × p noise-free outputs (same run, no noise)
  SampleLayout layout;         // of U and Y: segments and scored rows (the log's flags);
                               // one segment, every row scored, for an unflagged run
  double cf_avg = 0.0;         // crest factor over the experiment, averaged over inputs
  double cf_period_avg = 0.0;  // over each input's active span (its periods), averaged
  double pips_avg = 0.0;
  double limit_scale = 1.0;         // < 1: scaled as a whole to fit the input limits
  IdentificationResult identified;  // on the rows `layout` scores
  double fit_avg = 0.0;             // own data, averaged over outputs (5.5.1)
  double crossfit_avg = 0.0, crossfit_best = 0.0, crossfit_worst = 0.0;
  /// Issue 45 (host/measures/cross_fit.hpp): the true plant's fit on this run (5.5.1, the
  /// rows and the rule of a cross-fit, averaged over outputs; the bound its noise sets), the
  /// run that gives this model's worst cross-fit and the truth's fit there, and this model's
  /// loss against the truth over the other runs, in points of fit %. NaN (and -1) when the
  /// truth is not known or a fit is NaN.
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double truth_fit = kUnknown;
  int crossfit_worst_on = -1;  // index into CampaignResult::experiments
  double truth_fit_on_worst = kUnknown;
  double loss_avg = kUnknown, loss_worst = kUnknown;
  int loss_worst_on = -1;  // index into CampaignResult::experiments
  Balance balance_clean;   // on the noise-free outputs: a property of the excitation
  Balance balance_noisy;   // on the measured (noisy) outputs: the scored rows, each segment
                           // about its own mean
};

/// SPEC §4, thesis §6.3: every experiment as long as every other ("T_L = 4080 min was the
/// same for all cases"), so that no design's verdict rests on more data. `lengths`: (design,
/// samples). Unequal lengths throw std::invalid_argument naming every length, unless
/// `allow_unequal` (then `say` gets a warning with them).
void check_equal_lengths(const std::vector<std::pair<std::string, Eigen::Index>>& lengths,
                         bool allow_unequal, const std::function<void(const std::string&)>& say);

struct CampaignResult {
  std::string plant;
  std::vector<std::string> input_names, output_names;
  std::vector<std::string> input_units, output_units;  // "-" when dimensionless
  double noise_variance = 0.0;                         // what the runs used
  bool sized_by_static_output = false;
  GainAnalysis true_gain;
  GainAnalysis design_gain;               // what the designs used
  std::string design_gain_source;         // "true G(0)" or "step test (stepSeq)"
  std::optional<GainAnalysis> step_gain;  // the step test's estimate, when it has one
  std::optional<Structure> structure;     // forced on every element (options.structure), or BIC's
  bool truth_known = true;                // options.truth_known
  std::vector<Experiment> experiments;
  Eigen::MatrixXd crossfit;  // fit(a, b): model a on data b, averaged over outputs (b's
                             // scored rows, the model from rest at each of b's segments)
};

struct Design;
struct PresetInfo;

/// One experiment of the campaign (what run_campaign does per design, also used by
/// host/montecarlo): `design` run noise-free and measured (options.measured_run, or
/// simulated on options.plant with the noise of seed options.seed + preset.number),
/// identified on one thread with T_p ≤ max_time_constant_min (in options.structure, if
/// set), balance on both runs along `true_gain`'s output directions, and (options.truth_known)
/// the true plant's fit on the measured run. The cross-fit fields stay 0. Uses a plant of its own:
/// callable from several threads at once.
Experiment run_experiment(const Design& design, const PresetInfo& preset,
                          const CampaignOptions& options, double noise_variance,
                          const GainAnalysis& true_gain, double max_time_constant_min);

/// Runs the campaign; `progress` (may be empty) gets one line per step for the terminal
/// (called from the pool's threads, one call at a time). Throws std::invalid_argument for
/// an unknown plant or a plant without a case study.
CampaignResult run_campaign(const CampaignOptions& options,
                            const std::function<void(const std::string&)>& progress);

}  // namespace excite::host
