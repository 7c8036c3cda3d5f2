// SPDX-License-Identifier: MIT
#pragma once
// One (design, seed) unit of a Monte Carlo run: the campaign's experiment (host/campaign
// run_experiment: design → simulate noise-free and with the seed's noise → identify →
// balance), its model cross-validated on the other designs' runs of the same seed, its G(0)
// judged by the accuracy criterion, and the same identification repeated on the first 5, 10,
// … % of the run (the prefix of the same run, not simulated again).

#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/campaign/closed_loop_experiment.hpp"
#include "host/design/presets.hpp"
#include "host/design/prior_knowledge.hpp"
#include "host/identify/identify.hpp"
#include "host/measures/accuracy.hpp"
#include "host/montecarlo/work.hpp"
#include "sim/control/controller.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/lti/transfer_matrix.hpp"

namespace excite::host::montecarlo {

/// The criterion on the first `percent` % of the run (samples = ⌊N · percent / 100⌋).
struct LengthPoint {
  int percent = 100;
  long long samples = 0;
  bool met = false;
};

/// Where a unit's time went: CPU seconds of the thread that ran it, per stage. Not kept in
/// the unit's file (they differ from run to run).
struct UnitTimes {
  double experiment_s = 0.0;  // run_experiment: simulate twice, identify, balance
  double crossval_s = 0.0;    // the other designs' runs of the seed simulated, model fitted
  double lengths_s = 0.0;     // identifications on the prefixes of the test-length grid
};

/// What a unit keeps (DIR/units/…json, records.hpp); every figure the summary needs.
struct UnitResult {
  std::string design;  // acronym
  int number = 0;      // Table 6.1
  std::uint64_t seed = 0;
  long long samples = 0;
  double sample_time_min = 0.0;
  double fit_avg = 0.0;       // own data, % averaged over outputs (5.5.1)
  double crossfit_avg = 0.0;  // over the other designs of the run, same seed (NaN: none)
  double crossfit_worst = 0.0;
  double ratio = 0.0, upsilon = 0.0;              // noise-free balance (5.5.2, 6.2.1)
  double ratio_noisy = 0.0, upsilon_noisy = 0.0;  // on the measured outputs
  std::vector<double> singular_values;  // of the identified G(0); empty when not identified
  std::vector<double> gain;             // the identified G(0), row-major; empty likewise
  std::vector<double> true_gain;        // the seed's perturbed true G(0), row-major; empty: nominal
  Accuracy accuracy;                    // on the whole run, against the seed's true plant
  std::vector<LengthPoint> lengths;     // length_grid(config), the last one the whole run
  // Closed loop, against the CV test limits (the controller file's [[cv]] limits; none: NaN
  // and 0): the measured CVs' largest excursion as a share of the limit on its side (> 1: a
  // violation), and the rows where any CV was outside its limits.
  double cv_peak_ratio = std::numeric_limits<double>::quiet_NaN();
  long long cv_violation_rows = 0;
  // Why the unit was not run; empty: it was. Closed loop: the controller refused the seed's
  // perturbed model (not integrally controllable for the plant) — a DMC that would not be
  // commissioned. Such a unit meets nothing, and the summary counts it apart (summary.hpp).
  std::string not_run;
  UnitTimes times;  // not in the file
};

/// What every unit of a run shares, made once (designs are seed-free) and read-only after.
struct Prepared {
  Config config;
  CampaignOptions campaign;                    // plant, threads = 1; seed set per unit
  TruePlant truth;                             // the nominal plant's
  std::optional<sim::TransferMatrix> nominal;  // set when config.perturb_percent > 0
  double max_time_constant_min = 0.0;          // β·τ_H of the case study (SPEC §6)
  std::vector<PresetInfo> presets;             // config.designs'
  std::vector<Design> designs;                 // closed loop: the closed-loop designs
  // Closed loop (config.closed_loop.on()): the controller file, read once; its model's
  // nominal transfer matrix when the model is perturbed per seed.
  std::optional<sim::control::ControllerFile> controller;
  std::optional<sim::TransferMatrix> controller_model;
  Eigen::VectorXd cv_low, cv_high;  // the CV test limits (deviations); empty: none known
};

/// Whether the rows from_rows … to_rows − 1 of a run add nothing new to its first from_rows:
/// no input moves (u(k) ≠ u(k − 1), any input) at any row k ≥ from_rows − ⌈max_delay/T⌉ − 1,
/// so every step or excitation of the longer prefix reached the outputs within the shorter
/// one (a delay T_d ≤ max_delay shows a move at k from row k + ⌈T_d/T⌉ on), and the added rows
/// carry only the continued response to moves the shorter prefix already saw, and noise.
/// False when from_rows is 0 or beyond to_rows.
bool nothing_new(const Eigen::MatrixXd& U, Eigen::Index from_rows, Eigen::Index to_rows,
                 double sample_time_min, double max_delay_min);

/// The test-length grid of one experiment: the criterion on the first ⌊N·p/100⌋ rows of its
/// run for each p of `grid` (ascending; 100: the experiment's own identification).
struct GridEvaluation {
  std::vector<LengthPoint> points;  // one per grid length
  // Per grid length below 100 %: the prefix's identification; nullopt when too short.
  std::vector<std::optional<IdentificationResult>> results;
  int identified = 0;   // prefixes identified
  int warm = 0;         // of them only from the previous length's model (settled, below)
  int polished = 0;     // of those only polished (nothing_new)
  int checked = 0;      // fitted both cold and warm (before settling)
  int warm_better = 0;  // of those where the warm fit's BIC was lower and it was kept
};
/// GridStart::cold identifies every prefix from scratch. GridStart::warm: the first
/// identifiable prefix cold; then each length is fitted cold and from the previous length's
/// model, the lower BIC (prefix_bic) kept — the cold fit unless the warm one is lower by more
/// than 0.01 — until the warm fit has ended at the cold fit's optimum or a better one (BIC
/// below cold's + 0.01) at three consecutive lengths (checked again at a length where a row's
/// residual rms exceeds the previous length's by more than 10 %); from then on each length only
/// from the previous one's model, and only polished where nothing_new (host/montecarlo/README.md,
/// "The length grid warm-started"). `reference` (closed loop: the test signal r, N × channels;
/// empty: open loop): each prefix identified two-stage, stage 1 (project_on_reference) on the
/// prefix's rows of U and r alone, so no later row shapes û; a prefix too short for stage 1's
/// lags, or with r still 0 throughout, is not identified.
GridEvaluation evaluate_length_grid(const Prepared& prepared, const TruePlant& truth,
                                    const Experiment& experiment, const std::vector<int>& grid,
                                    GridStart start,
                                    const Eigen::MatrixXd& reference = Eigen::MatrixXd());

/// The BIC of a fit summed over its rows (host/identify row_criterion: each row's output error
/// over Y's rows, the free parameters of its estimated elements); Y the outputs it was fitted
/// on.
double prefix_bic(const IdentificationResult& fit, const Eigen::MatrixXd& Y);
/// Designs every design of `config` (on `threads` threads). Throws std::invalid_argument for
/// a plant without a case study.
std::unique_ptr<Prepared> prepare(const Config& config, int threads);

/// Closed loop (closed_loop_unit.cpp): reads the controller file, makes its controller on its
/// own model for the nominal plant (so a file that does not fit the plant is refused once,
/// not per seed), checks that the model can be perturbed when asked to (a linear library
/// plant, a DMC) and designs the closed-loop designs (host/campaign/closed_loop_designs.hpp).
/// Throws std::invalid_argument naming the option, or config::Error the file's field.
void prepare_closed_loop(Prepared& prepared, const PriorKnowledge& prior);

/// Closed loop: the controller of seed `seed` on a plant of G(0) `plant_gain` — the
/// controller file's, on its model perturbed for controller_model_seed(seed) when asked — or,
/// when the controller refuses that model for this plant (a DMC's model not integrally
/// controllable: make_controller.hpp), no controller and the refusal's message.
struct SeedController {
  std::unique_ptr<sim::control::Controller> controller;  // null: refused
  std::string refused;
};
SeedController seed_controller(const Prepared& prepared, std::uint64_t seed,
                               const Eigen::MatrixXd& plant_gain);

/// Closed loop: unit's design run on `plant` (the seed's true plant, G(0) in `truth`) under
/// `controller` (seed_controller's), with noise seed 100·s + number and the coloured
/// disturbance, identified as config.closed_loop.method says.
ClosedLoopRun closed_loop_experiment(const Prepared& prepared, const Unit& unit, sim::Plant& plant,
                                     sim::control::Controller& controller, const TruePlant& truth);

/// CPU time of the calling thread, seconds (CLOCK_THREAD_CPUTIME_ID).
double thread_cpu_s();

/// Runs one unit on the calling thread: with a perturbation, on the seed's perturbed plant
/// (perturb.hpp), every run of the unit (its own, and the other designs' for the
/// cross-validation) on that plant, the balance along its output directions and the
/// criterion against its G(0).
UnitResult run_unit(const Prepared& prepared, const Unit& unit);

}  // namespace excite::host::montecarlo
