// SPDX-License-Identifier: MIT
#pragma once
// `excite simulate`: a planned experiment run open loop on a simulated plant, written as
// a run log (firmware/runlog/README.md) exactly like the gateway writes one.

#include <Eigen/Core>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "firmware/plan/plan.hpp"
#include "firmware/runlog/format.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// The most rows one simulation writes (periods × plan samples, or a step's samples): what
/// the identification reads (host/README.md, "Limits"). Checked before any work.
inline constexpr std::uint64_t kMaxSimulatedRows = 100'000;

struct SimulationOptions {
  double noise_variance = 0.0;  // per output, Gaussian (case study: 0.03)
  std::uint64_t seed = 1;       // of the noise (and of the disturbance, another stream)
  std::uint32_t periods = 1;    // the table played this many times back to back
  // The coloured output disturbance (sim/lti/disturbance.hpp): first-order filtered noise of
  // this stationary standard deviation (0: none) and time constant (minutes), per output.
  double disturbance_std = 0.0;
  double disturbance_tau_min = 0.0;
};

/// What a closed-loop run (closed_loop.hpp) records beside u and y: the v4 columns
/// (firmware/runlog/README.md, "Version 4"), deviations, one row per sample.
struct ClosedLoopRecord {
  runlog::Excitation excitation = runlog::Excitation::setpoint;
  std::string controller;                        // "<kind> <file>", the `# controller:` line
  std::vector<std::size_t> r_channels;           // outputs (setpoint) or inputs (mv) r moves
  Eigen::MatrixXd r;                             // N × r_channels: the test signal as designed
  Eigen::MatrixXd uc;                            // N × inputs: the controller's output (before the
                                                 // dither and any clamp) the plant got at row k
  Eigen::MatrixXd ysp;                           // N × outputs: the setpoints in force
  std::vector<std::vector<runlog::MvState>> st;  // N rows × inputs
  int held_steps = 0;         // controller steps that held their output (StepStatus::held)
  int qp_fallback_steps = 0;  // DMC steps at the QP's iteration cap (StepStatus::qp_fallback)
  int max_qp_iterations = 0;  // the most active-set iterations of one step
};

/// What a run log holds, in memory.
struct SimulatedRun {
  std::string plant;
  std::string plan;
  std::string producer;  // the run log's `# producer:` line, set by the command
  double sample_time_min = 0.0;
  runlog::TimeScales time_scales;  // the plan's τ_H, β, T_sw (0: not known), into the header
  std::vector<std::string> input_names, input_units, output_names, output_units;
  Eigen::VectorXd input_baseline;               // absolute inputs at the operating point
  Eigen::MatrixXd du;                           // N × inputs, deviations
  Eigen::MatrixXd dy;                           // N × outputs, deviations (with noise)
  std::optional<ClosedLoopRecord> closed_loop;  // set: a closed-loop run, written as v4
};

/// Runs `plan` on `plant`. Throws std::invalid_argument when the plan's channel count
/// differs from the plant's inputs, or periods is 0.
SimulatedRun simulate_plan(const plan::Plan& plan, std::string plan_label, sim::Plant& plant,
                           const SimulationOptions& options);

/// Step responses: input `input` (by name) moved by `amplitude` at t = 0 for `samples`
/// samples of `sample_time_min`, the other inputs at rest.
SimulatedRun simulate_step(sim::Plant& plant, const std::string& input, double amplitude,
                           std::uint32_t samples, double sample_time_min,
                           const SimulationOptions& options);

/// Adds the coloured output disturbance of `options` (nothing when its std is 0) to Y
/// (N × outputs) row by row. Throws std::invalid_argument for a std > 0 with τ ≤ 0.
void add_disturbance(Eigen::MatrixXd& y, double sample_time_min, const SimulationOptions& options);

/// Writes the run log whole or not at all (host/output/whole_file.hpp: a failed write
/// leaves the old file, if any, untouched). v3 for an open-loop run, v4 when
/// `run.closed_loop` is set. Throws std::runtime_error naming the path and the
/// writer's reason.
void write_run_log(const SimulatedRun& run, const std::filesystem::path& path);

}  // namespace excite::host
