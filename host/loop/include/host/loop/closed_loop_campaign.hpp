// SPDX-License-Identifier: MIT
#pragma once
// The campaign with the controller on (issue 42 §4: `excite campaign --controller FILE
// [--loop] [--excitation setpoint|mv]`). Its designs are the closed-loop ones of `excite
// design --excitation`: every plain (not directional) preset of Table 6.1 as a setpoint
// excitation (r on the CV setpoints, each CV at a fraction of its test limit; the
// controller makes the rotation u ≈ G(0)⁻¹ r) or as an MV dither. Each is run closed loop —
// through the real excite-gateway to `excite-plant --controller FILE` in lock-step
// (stream_in_the_loop with loop-config's closed-loop pair; the gateway writes run-log v4),
// or in process (host/simulate/closed_loop.hpp) — and identified as `excite identify` does
// a v4 log: two-stage, the direct fit beside it (host/identify/closed_loop.hpp). Each run is
// then judged as the open-loop campaign judges its runs (SPEC §6): the balance of its
// outputs along the true G(0)'s output directions (5.5.2, 6.2.1) and every two-stage model
// on every run (the cross-validation, host/measures/cross_fit.hpp).

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/campaign/closed_loop_designs.hpp"
#include "host/identify/closed_loop.hpp"
#include "host/loop/stream.hpp"
#include "host/measures/cross_fit.hpp"
#include "host/simulate/closed_loop_speed.hpp"

namespace excite::host {

struct ClosedLoopCampaignOptions {
  std::string plant;       // a library plant with a case study
  std::string controller;  // the controller file (sim/control/README.md)
  /// Preset acronyms to run, in this order; empty: every plain preset of Table 6.1.
  std::vector<std::string> designs;
  ClosedLoopDesignOptions design;  // setpoint or MV dither, CV limits, the MVs' room
  double noise_variance = -1.0;    // < 0: the case study's
  std::uint64_t seed = 1;          // design number e uses seed + e (as the open-loop campaign)
  bool loop = false;               // through the real gateway (programs), else in process
  LoopPrograms programs;
  int threads = 1;  // designs run and identified in parallel
};

struct ClosedLoopExperiment {
  int number = 0;       // Table 6.1
  std::string name;     // the preset's acronym
  std::string run_log;  // relative to the campaign's folder: runs/NN-name/run.csv
  std::string model;    // models/NN-name.json
  std::size_t rows = 0;
  std::size_t rows_mv_limited = 0;  // rows where an MV was clamped, wound up or in manual
  ClosedLoopIdentification identified;
  Balance balance;  // of the scored outputs about their segment means, along the true G(0)'s
                    // output directions: what the controller made of r (5.5.2, 6.2.1)
  double truth_fit = CrossFitFigures::kNaN;  // the true plant's mean fit % on this run
  Eigen::VectorXd crossfit;  // the two-stage model's mean fit % on every run, in run order
  CrossFitFigures cross;     // over the other runs, losses against truth_fit
};

/// The campaign's designs and runs. Setpoint designs take (4.2.3)'s τ_L from the loop's speed
/// by default (options.design.switching = "loop": setpoint_pace, closed_loop_designs.hpp).
struct ClosedLoopCampaign {
  double tau_low_min = 0.0;                   // the designs' τ_L
  std::optional<ClosedLoopSpeed> loop_speed;  // when it is the loop's: what the loop gave
  std::vector<ClosedLoopExperiment> runs;     // in the order of the designs
};

/// Runs every design into `dir` (runs/NN-name/: the plan, run.csv, and in the loop the
/// configuration pair, the plant's run log and its controller log; models/NN-name.json: the
/// two-stage model with its `closed_loop` block). `say` (may be empty) gets a line per run.
/// Throws std::invalid_argument (one message form) for a bad option, what the controller
/// file's reader, stream_in_the_loop and identification throw.
ClosedLoopCampaign run_closed_loop_campaign(const ClosedLoopCampaignOptions& options,
                                            const std::filesystem::path& dir,
                                            const std::function<void(const std::string&)>& say);

}  // namespace excite::host
