// SPDX-License-Identifier: MIT
#include "host/simulate/closed_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <vector>

#include "sim/lti/disturbance.hpp"
#include "sim/lti/noise.hpp"

namespace excite::host {
namespace {

std::string text(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void check(const Eigen::MatrixXd& r, double T, sim::Plant& plant, const sim::control::Controller& c,
           const ClosedLoopOptions& loop) {
  const bool sp = loop.excitation == runlog::Excitation::setpoint;
  const int side = sp ? plant.outputs() : plant.inputs();
  if (r.cols() != side) {
    throw std::invalid_argument(std::string("plan channels = ") + std::to_string(r.cols()) +
                                ", expected " + std::to_string(side) + " (the " +
                                (sp ? "outputs" : "inputs") + " of " + plant.name() + " for " +
                                (sp ? "setpoint" : "mv") + " excitation)");
  }
  if (r.rows() < 2 || static_cast<std::uint64_t>(r.rows()) > kMaxSimulatedRows) {
    throw std::invalid_argument("closed-loop rows = " + std::to_string(r.rows()) +
                                ", expected 2 to " + std::to_string(kMaxSimulatedRows));
  }
  if (!r.allFinite()) throw std::invalid_argument("r = (not finite), expected finite values");
  if (c.inputs() != plant.inputs() || c.outputs() != plant.outputs()) {
    throw std::invalid_argument("controller size = " + std::to_string(c.outputs()) + "x" +
                                std::to_string(c.inputs()) + ", expected " +
                                std::to_string(plant.outputs()) + "x" +
                                std::to_string(plant.inputs()) + " as " + plant.name());
  }
  if (std::abs(c.sample_time_min() - T) > 1e-9 * T) {
    throw std::invalid_argument("controller sample_time_min = " + text(c.sample_time_min()) +
                                ", expected the plan's " + text(T));
  }
  for (const Eigen::VectorXd* box : {&loop.mv_min, &loop.mv_max}) {
    if (box->size() != 0 && box->size() != plant.inputs()) {
      throw std::invalid_argument("MV box size = " + std::to_string(box->size()) + ", expected " +
                                  std::to_string(plant.inputs()));
    }
  }
}

}  // namespace

void set_controller(ClosedLoopOptions& loop, const sim::control::ControllerFile& file,
                    const std::string& file_label) {
  loop.controller =
      std::string(file.kind == sim::control::ControllerKind::dmc ? "dmc " : "pi ") + file_label;
  loop.mv_min.resize(static_cast<Eigen::Index>(file.dmc.mv.size()));
  loop.mv_max.resizeLike(loop.mv_min);
  for (std::size_t j = 0; j < file.dmc.mv.size(); ++j) {
    loop.mv_min(static_cast<Eigen::Index>(j)) = file.dmc.mv[j].min;
    loop.mv_max(static_cast<Eigen::Index>(j)) = file.dmc.mv[j].max;
  }
}

namespace {

// The run's header from the plant, its N × n inputs and N × p outputs to be filled.
SimulatedRun empty_run(const sim::Plant& plant, std::string plan_label, double sample_time_min,
                       Eigen::Index N) {
  SimulatedRun run;
  run.plant = plant.name();
  run.plan = std::move(plan_label);
  run.sample_time_min = sample_time_min;
  run.input_names = plant.input_names();
  run.input_units = plant.input_units();
  run.output_names = plant.output_names();
  run.output_units = plant.output_units();
  run.input_baseline = plant.input_baseline();
  run.du.resize(N, plant.inputs());
  run.dy.resize(N, plant.outputs());
  return run;
}

// The loop's record: the excitation r, the controller's moves and setpoints to be filled,
// every MV's state ok until a limit clamps it.
ClosedLoopRecord empty_record(const ClosedLoopOptions& loop, const Eigen::MatrixXd& r, int n,
                              int p) {
  const Eigen::Index N = r.rows();
  ClosedLoopRecord rec;
  rec.excitation = loop.excitation;
  rec.controller = loop.controller;
  for (Eigen::Index c = 0; c < r.cols(); ++c) rec.r_channels.push_back(static_cast<std::size_t>(c));
  rec.r = r;
  rec.uc.resize(N, n);
  rec.ysp = Eigen::MatrixXd::Zero(N, p);
  rec.st.assign(static_cast<std::size_t>(N),
                std::vector<runlog::MvState>(static_cast<std::size_t>(n), runlog::MvState::ok));
  return rec;
}

}  // namespace

SimulatedRun simulate_closed_loop(const Eigen::MatrixXd& r, std::string plan_label,
                                  double sample_time_min, sim::Plant& plant,
                                  sim::control::Controller& controller,
                                  const ClosedLoopOptions& loop, const SimulationOptions& options) {
  check(r, sample_time_min, plant, controller, loop);
  if (options.noise_variance < 0.0 || !std::isfinite(options.noise_variance)) {
    throw std::invalid_argument("noise variance = " + text(options.noise_variance) +
                                ", expected a finite number >= 0");
  }
  const bool sp = loop.excitation == runlog::Excitation::setpoint;
  const int n = plant.inputs();
  const int p = plant.outputs();
  const Eigen::Index N = r.rows();

  SimulatedRun run = empty_run(plant, std::move(plan_label), sample_time_min, N);
  ClosedLoopRecord rec = empty_record(loop, r, n, p);

  std::unique_ptr<sim::MeasurementNoise> noise;
  if (options.noise_variance > 0.0) {
    noise = std::make_unique<sim::MeasurementNoise>(p, options.noise_variance, options.seed);
  }
  std::unique_ptr<sim::ColouredDisturbance> disturbance;
  if (options.disturbance_std > 0.0) {
    disturbance = std::make_unique<sim::ColouredDisturbance>(
        p, options.disturbance_std, options.disturbance_tau_min, sample_time_min,
        sim::disturbance_seed(options.seed));
  }

  plant.reset(sample_time_min);
  controller.reset();
  // Sample k, in the order excite-plant --controller takes it (sim/server, closed_loop.cpp):
  // the controller steps on the CVs of k − 1 (at rest before k = 0) with the setpoint and the
  // known offsets in force at k, then the plant gets its move plus the dither.
  std::vector<double> u(static_cast<std::size_t>(n)), uc(u.size(), 0.0), offsets(u.size());
  std::vector<double> y(static_cast<std::size_t>(p), 0.0), ysp(y.size());
  for (Eigen::Index k = 0; k < N; ++k) {
    for (int i = 0; i < p; ++i) {
      ysp[static_cast<std::size_t>(i)] = sp ? r(k, i) : 0.0;
      rec.ysp(k, i) = ysp[static_cast<std::size_t>(i)];
    }
    for (int j = 0; j < n; ++j) {
      offsets[static_cast<std::size_t>(j)] = !sp && loop.dither_known ? r(k, j) : 0.0;
    }
    const sim::control::StepReport report = controller.step(y, ysp, offsets, uc);
    rec.held_steps += report.status == sim::control::StepStatus::held ? 1 : 0;
    rec.qp_fallback_steps += report.status == sim::control::StepStatus::qp_fallback ? 1 : 0;
    rec.max_qp_iterations = std::max(rec.max_qp_iterations, report.qp_iterations);
    for (int j = 0; j < n; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      rec.uc(k, j) = uc[jj];
      double v = uc[jj] + (sp ? 0.0 : r(k, j));
      runlog::MvState st = runlog::MvState::ok;
      if (loop.mv_min.size() != 0 && v <= loop.mv_min(j)) {
        v = loop.mv_min(j);
        st = runlog::MvState::clamped_low;
      } else if (loop.mv_max.size() != 0 && v >= loop.mv_max(j)) {
        v = loop.mv_max(j);
        st = runlog::MvState::clamped_high;
      }
      u[jj] = v;
      run.du(k, j) = v;
      rec.st[static_cast<std::size_t>(k)][jj] = st;
    }
    plant.step(u, y);
    if (noise) noise->add(y.data());
    if (disturbance) disturbance->add(y);
    for (int i = 0; i < p; ++i) run.dy(k, i) = y[static_cast<std::size_t>(i)];
  }
  run.closed_loop = std::move(rec);
  return run;
}

}  // namespace excite::host
