// SPDX-License-Identifier: MIT
#pragma once
// `excite simulate --controller`: a planned test run closed loop, in process (issue 41 §1):
// the plant (sim/plants) under a controller of sim/control, with excite's test signal r
// added either to the CV setpoints (`setpoint`: y_sp(k) = r(k)) or to the controller's MV
// output as a dither (`mv`: u(k) = u_c(k) + r(k)), the controller told of the dither as a
// known move or not. Measurement noise and the coloured output disturbance
// (SimulationOptions) act on what the controller reads and what the log records.
//
// Timing (sim/control/README.md, "The interface"): sim::Plant::step returns y(k) in the call
// that takes u(k), so the controller's output from y(k) is applied at k + 1 — the loop's one
// sample of delay, which a DMC's model states (`model.delay_samples = 1`). The order within a
// sample is excite-plant --controller's (sim/server/README.md, "Closed loop"), so a plan run
// here and through the gateway gives the same moves row by row (tests/hil/loop,
// closed_loop_equal_test.cpp). Row k of the log:
//   uc(k)  the controller's output at k, computed on y(k − 1) (0 before k = 0: at rest) with
//          the setpoints ysp(k) and the known offsets (mv: r(k)) in force at k,
//   r(k)   the test signal of plan row k,
//   u(k)   = clamp(uc(k) + r(k) [mv only], MV box): what the plant got, du in the log,
//   y(k)   the CVs at kT with noise and disturbance, dy in the log,
//   ysp(k) the setpoints in force at k (r(k) for setpoint excitation, else 0),
//   st(k)  clamped low/high when u(k) sits on its box limit, else ok.

#include <Eigen/Core>

#include <string>

#include "firmware/runlog/format.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/control/controller.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

struct ClosedLoopOptions {
  runlog::Excitation excitation = runlog::Excitation::setpoint;
  bool dither_known = true;  // mv: the controller gets r as its known offsets
  Eigen::VectorXd mv_min;    // the MV box on the applied u (empty: none), deviations
  Eigen::VectorXd mv_max;
  std::string controller;  // "<kind> <file>", the log's `# controller:` line
};

/// The controller file's part of the options: its MV box (a DMC file's [[mv]] limits; a PI
/// file has none) and the log's `# controller:` line, "<kind> <file_label>".
void set_controller(ClosedLoopOptions& loop, const sim::control::ControllerFile& file,
                    const std::string& file_label);

/// Runs the test signal `r` (N × outputs for setpoint excitation, N × inputs for mv; a
/// plan's table, make_table) on `plant` under `controller`, both reset first. Throws
/// std::invalid_argument (one message form) when r's width is not the excitation side's
/// channel count, the controller's sizes or sample time differ from the plant's and the
/// run's, or r has more than kMaxSimulatedRows rows.
SimulatedRun simulate_closed_loop(const Eigen::MatrixXd& r, std::string plan_label,
                                  double sample_time_min, sim::Plant& plant,
                                  sim::control::Controller& controller,
                                  const ClosedLoopOptions& loop, const SimulationOptions& options);

}  // namespace excite::host
