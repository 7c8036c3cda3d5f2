// SPDX-License-Identifier: MIT
#pragma once
// Identification of a transfer-function matrix of (6.1.1) elements (SPEC §6): every output
// is fitted as a multi-input single-output model, all n elements of the row together, by
// output error with the exact ZOH simulation of element.hpp (sim/lti).
//
// Per output:
//   1. Which inputs can be identified: an input that is zero throughout, or a linear
//      combination of other inputs, gets no parameters (status and reason instead).
//   2. Initialisation (finding the basin), two starts: (a) the row seen at once — an ARX
//      least-squares model of the whole row gives each element's part of the output, and
//      each element is fitted alone to its part (arx_start.hpp; exact on data the
//      structure fits); (b) a grid of unit-gain responses per input (delay × time constant
//      × shape) and coordinate sweeps that pick, per element, the grid response that most
//      lowers the output error with all gains re-estimated jointly. The better start is
//      polished, the other too when the two are not clearly ranked; the better end is kept.
//   3. Bounded Levenberg–Marquardt on the output error of all 4 parameters of every element
//      (gain, delay, two time constants), 0 ≤ T_d ≤ max_delay_min, 0 ≤ T_p ≤
//      max_time_constant_min; Jacobian by central differences per element.
//   4. Each element's structure (element.hpp: first order, two poles, two poles with a zero,
//      integrator, underdamped, underdamped with a lag and a zero) chosen by the row's BIC,
//      starting from the two-pole fit (structure_search.hpp), or one forced for all.
//   5. Standard errors from σ̂² (JᵀJ)⁻¹ over the parameters not on a bound, σ̂² = SSE/(N − P);
//      for the gains of inputs that move with others, the profile likelihood's interval
//      (inputs_together.hpp), which does not assume local linearity.
//   6. Per output, Ljung's residual tests; per element, a grade A–D (grade.hpp).
// The result also carries the fit % per output (5.5.1), the analysis of the identified
// G(0) (singular values, ξ_i, κ, RGA) and how well it is known (gain_uncertainty.hpp).

#include <Eigen/Dense>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "host/identify/gain_profile.hpp"
#include "host/identify/gain_uncertainty.hpp"
#include "host/identify/input_screen.hpp"
#include "host/identify/model.hpp"
#include "host/identify/residuals.hpp"
#include "host/identify/segments.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {

struct IdentifyOptions {
  double max_delay_min = 20.0;          // upper bound of T_d (thesis: 20 min)
  double max_time_constant_min = 0.0;   // upper bound of T_p; SPEC §6: β·τ_H of the prior
                                        // knowledge; 0 = the experiment length N·T
  int max_iterations = 200;             // Levenberg–Marquardt iterations per output
  int threads = 1;                      // outputs are fitted in parallel on this many threads
  Trend trend = Trend::none;            // per segment offset / line of each output fitted with
                                        // the model (segments.hpp)
  bool estimate_initial_state = false;  // per segment, each output's free response from an
                                        // unknown initial state (a record that starts
                                        // mid-test): an offset and decays exp(−t/τ) for τ =
                                        // T_p max / 2^k ≥ T, k = 0…5, fitted with the model
  std::optional<Structure> structure;   // every element in this structure; nullopt (auto):
                                        // chosen per element by BIC (structure_search.hpp)
  std::vector<Structure> structures;    // outputs × inputs, row by row: each element in its own
                                        // structure (an earlier model's, e.g. the whole run's
                                        // for a prefix of it); empty: `structure` decides
  // A warm start (the Monte Carlo test-length grid: the fit on 25 % of a run from the model on
  // 20 %): an earlier model of the same outputs × inputs. A row whose usable elements are all
  // estimated in it, each in the structure `structure` / `structures` force (any, when
  // chosen), is fitted from it instead of the ARX and grid starts (the response bank and the
  // ARX basis are then not built when no row needs them); the structure search then runs from
  // that fit as from the two-pole one (free to change structures unless forced), the local
  // optima are left as on every path. Any other row is fitted cold, as without it.
  std::optional<IdentifiedModel> start;
  // StartUse::polish: the rows started from `start` are only polished (bounded LM in their
  // structures, standard errors) — no search, no restarts: for data that add nothing new to
  // the data `start` was fitted on (the caller's judgement; host/montecarlo unit.cpp).
  enum class StartUse { first_start, polish };
  StartUse start_use = StartUse::first_start;
  // Each gain whose element's joint 95 % region does not tell it from zero (or whose dynamics
  // the data do not determine) gets its projected interval, and the gains tied to it theirs
  // (gain_profile.hpp, project_gains_near_zero): the reported 95 % intervals. Off where none
  // is read: the Monte Carlo length grid (it judges G(0) against the truth) and the adaptive
  // test's segments (the stop rule reads the covariance). It costs an alatiqi4x4 closed-loop
  // identification about 11 %, an open-loop one up to 35 %.
  bool project_gains = true;
  // How far each projection reaches (gain_profile.hpp): the two-stage estimate's stage 2 sets
  // instrument_step_follows (its instrumental-variable step takes the gains' bias off).
  ProjectionScope projection_scope = ProjectionScope::fit_is_final;
};

/// Per-output diagnostics of the fit.
struct OutputFit {
  double fit_percent = 0.0;      // (5.5.1) on the scored estimation rows; NaN when constant there
  double residual_rms = 0.0;     // ‖ŷ − y‖ / √N over the N scored rows, output units
  int iterations = 0;            // Levenberg–Marquardt iterations used
  bool converged = false;        // stopped on a convergence test, not the iteration limit
  ResidualTests residual_tests;  // Ljung's whiteness and independence tests on the scored
                                 // rows (residuals.hpp); they grade the row's elements
  // How well the data tell the row's usable inputs apart (inputs_together.hpp), one entry
  // per usable input in ascending order; inputs below kCannotSplit had their gains profiled.
  InputSeparation separation;
  std::string inputs_together;  // describe_together(): "" when every input moves on its own
  // Degrees of freedom of the noise model's low-frequency level, which the row's gain SEs
  // scale with (low_frequency_level_dof, noise_model.hpp); +∞ where no noise model was fitted
  // or it is white: the SEs are then read with z.
  double noise_level_dof = std::numeric_limits<double>::infinity();
};

struct IdentificationResult {
  IdentifiedModel model;
  std::vector<OutputFit> fits;       // one per output
  std::optional<GainAnalysis> gain;  // of the identified G(0), when every K is estimated
  std::optional<GainUncertainty> gain_uncertainty;  // σ_i ±, direction angles, minors; with gain
  std::string gain_unavailable_reason;              // why `gain` is empty
};

/// Identifies the model from U (N × n inputs) and Y (N × p outputs) sampled every T_min
/// minutes. Throws std::invalid_argument for: size mismatch, empty data, NaN/inf entries,
/// T_min not finite and > 0, bad options, or fewer samples than
/// ⌈max_delay_min / T⌉ + 10·(4n) (the delay range plus ten samples per parameter).
IdentificationResult identify(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T_min,
                              const IdentifyOptions& options = {});

/// The same on the rows of `layout` (segments.hpp): the model simulated from rest at each
/// segment's start, the output error, fit % and residual over the scored rows only; the
/// sample-count check counts scored rows. Throws std::invalid_argument also when the layout
/// does not describe U's rows (naming the segment or row).
IdentificationResult identify(const Eigen::MatrixXd& U, const Eigen::MatrixXd& Y, double T_min,
                              const SampleLayout& layout, const IdentifyOptions& options = {});

/// Fills result.gain (the analysis of the model's G(0)) when every gain is estimated and
/// finite, else result.gain_unavailable_reason; result.gain_uncertainty when also every row's
/// gain covariance is known. identify() calls it; a caller that changes rows of the model
/// calls it again.
void analyse_identified_gain(IdentificationResult& result);

/// Smallest N that identify() accepts for n inputs.
Eigen::Index minimum_samples(int inputs, double T_min, const IdentifyOptions& options = {});

}  // namespace excite::host
