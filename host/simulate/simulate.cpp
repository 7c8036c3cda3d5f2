// SPDX-License-Identifier: MIT
#include "host/simulate/simulate.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

#include "firmware/runlog/writer.hpp"
#include "host/design/table.hpp"
#include "host/output/whole_file.hpp"
#include "sim/lti/disturbance.hpp"
#include "sim/lti/noise.hpp"

namespace excite::host {
namespace {

SimulatedRun describe(sim::Plant& plant, double sample_time_min) {
  SimulatedRun run;
  run.plant = plant.name();
  run.sample_time_min = sample_time_min;
  run.input_names = plant.input_names();
  run.input_units = plant.input_units();
  run.output_names = plant.output_names();
  run.output_units = plant.output_units();
  run.input_baseline = plant.input_baseline();
  return run;
}

void respond(sim::Plant& plant, SimulatedRun& run, const SimulationOptions& options) {
  run.dy = plant.simulate(run.du, run.sample_time_min);
  if (options.noise_variance > 0.0) {
    sim::MeasurementNoise noise(plant.outputs(), options.noise_variance, options.seed);
    noise.add(run.dy);
  } else if (options.noise_variance < 0.0) {
    throw std::invalid_argument("noise variance = " + std::to_string(options.noise_variance) +
                                ", expected >= 0");
  }
  add_disturbance(run.dy, run.sample_time_min, options);
}

}  // namespace

void add_disturbance(Eigen::MatrixXd& y, double sample_time_min, const SimulationOptions& options) {
  if (options.disturbance_std == 0.0) return;
  sim::ColouredDisturbance d(static_cast<int>(y.cols()), options.disturbance_std,
                             options.disturbance_tau_min, sample_time_min,
                             sim::disturbance_seed(options.seed));
  std::vector<double> row(static_cast<std::size_t>(y.cols()));
  for (Eigen::Index k = 0; k < y.rows(); ++k) {
    for (Eigen::Index i = 0; i < y.cols(); ++i) row[static_cast<std::size_t>(i)] = y(k, i);
    d.add(row);
    for (Eigen::Index i = 0; i < y.cols(); ++i) y(k, i) = row[static_cast<std::size_t>(i)];
  }
}

SimulatedRun simulate_plan(const plan::Plan& plan, std::string plan_label, sim::Plant& plant,
                           const SimulationOptions& options) {
  if (static_cast<int>(plan.recipe.channels) != plant.inputs()) {
    throw std::invalid_argument("plan has " + std::to_string(plan.recipe.channels) +
                                " channels, plant " + plant.name() + " has " +
                                std::to_string(plant.inputs()) + " inputs, expected equal");
  }
  if (options.periods == 0) throw std::invalid_argument("periods = 0, expected at least 1");
  const std::uint64_t rows = std::uint64_t{options.periods} * plan.recipe.samples;
  if (rows > kMaxSimulatedRows) {
    throw std::invalid_argument("--periods x plan samples = " + std::to_string(options.periods) +
                                " x " + std::to_string(plan.recipe.samples) + " = " +
                                std::to_string(rows) + " rows, expected at most " +
                                std::to_string(kMaxSimulatedRows) + " (host/README.md, Limits)");
  }
  SimulatedRun run = describe(plant, plan.meta.sample_time_min);
  run.plan = std::move(plan_label);
  run.time_scales = {plan.meta.tau_high_min, plan.meta.beta, plan.meta.switch_time_min};
  const Table table = make_table(plan.recipe);
  run.du.resize(table.rows() * options.periods, table.cols());
  for (std::uint32_t p = 0; p < options.periods; ++p)
    run.du.middleRows(p * table.rows(), table.rows()) = table;
  respond(plant, run, options);
  return run;
}

SimulatedRun simulate_step(sim::Plant& plant, const std::string& input, double amplitude,
                           std::uint32_t samples, double sample_time_min,
                           const SimulationOptions& options) {
  const std::vector<std::string> names = plant.input_names();
  const auto at = std::find(names.begin(), names.end(), input);
  if (at == names.end()) {
    std::string known;
    for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("step input = \"" + input + "\", expected one of: " + known);
  }
  if (samples < 2 || samples > kMaxSimulatedRows) {
    throw std::invalid_argument("samples = " + std::to_string(samples) + ", expected 2 to " +
                                std::to_string(kMaxSimulatedRows));
  }
  SimulatedRun run = describe(plant, sample_time_min);
  char amplitude_text[32];
  std::snprintf(amplitude_text, sizeof amplitude_text, "%g", amplitude);
  run.plan = "step " + input + "=" + amplitude_text;
  run.du = Eigen::MatrixXd::Zero(samples, plant.inputs());
  run.du.col(at - names.begin()).setConstant(amplitude);
  respond(plant, run, options);
  return run;
}

void write_run_log(const SimulatedRun& run, const std::filesystem::path& path) {
  std::vector<runlog::Channel> inputs, outputs;
  for (std::size_t j = 0; j < run.input_names.size(); ++j)
    inputs.push_back({run.input_names[j], run.input_units[j]});
  for (std::size_t i = 0; i < run.output_names.size(); ++i) {
    outputs.push_back({run.output_names[i], run.output_units[i]});
  }
  runlog::Header header{run.plant, run.plan,     run.sample_time_min, inputs,
                        outputs,   run.producer, run.time_scales};
  const ClosedLoopRecord* loop = run.closed_loop ? &*run.closed_loop : nullptr;
  if (loop != nullptr) {
    header.closed_loop = {true, loop->excitation, loop->controller, loop->r_channels};
  }

  WholeFile file(path);
  std::vector<char> buffer(
      std::max<std::size_t>(runlog::max_closed_loop_row_chars(inputs.size(), outputs.size(),
                                                              loop ? loop->r_channels.size() : 0),
                            1 << 16));
  runlog::FileWriter writer(file.stream(), header, buffer);
  const auto fail = [&](runlog::WriteStatus status) {
    const int error = errno;  // a stream error's reason: disk full, file too large
    std::string reason(runlog::describe(status));
    if (std::ferror(file.stream()) != 0 && error != 0) reason = std::strerror(error);
    throw std::runtime_error(path.string() + ": cannot be written (" + reason + ")");
  };
  if (const auto s = writer.write_header(); s != runlog::WriteStatus::ok) fail(s);

  const auto n = static_cast<Eigen::Index>(inputs.size());
  const auto p = static_cast<Eigen::Index>(outputs.size());
  std::vector<double> du(static_cast<std::size_t>(n)), u(static_cast<std::size_t>(n)),
      dy(static_cast<std::size_t>(p));
  std::vector<double> r(loop ? loop->r_channels.size() : 0), uc(du.size()), ysp(dy.size());
  for (Eigen::Index k = 0; k < run.du.rows(); ++k) {
    for (Eigen::Index j = 0; j < n; ++j) {
      du[static_cast<std::size_t>(j)] = run.du(k, j);
      u[static_cast<std::size_t>(j)] = run.input_baseline(j) + run.du(k, j);
    }
    for (Eigen::Index i = 0; i < p; ++i) dy[static_cast<std::size_t>(i)] = run.dy(k, i);
    // No engine here: every row of the plan is applied as designed, so the state is running.
    runlog::Row row{static_cast<double>(k) * run.sample_time_min,
                    static_cast<std::uint64_t>(k),
                    du,
                    u,
                    dy,
                    0,
                    runlog::RunState::running};
    if (loop != nullptr) {
      const auto kk = static_cast<std::size_t>(k);
      for (std::size_t c = 0; c < r.size(); ++c) r[c] = loop->r(k, static_cast<Eigen::Index>(c));
      for (Eigen::Index j = 0; j < n; ++j) uc[static_cast<std::size_t>(j)] = loop->uc(k, j);
      for (Eigen::Index i = 0; i < p; ++i) ysp[static_cast<std::size_t>(i)] = loop->ysp(k, i);
      row.r = r;
      row.uc = uc;
      row.ysp = ysp;
      row.st = loop->st[kk];
      row.mode = runlog::LoopMode::test;
      for (const runlog::MvState st : loop->st[kk]) {
        if (st == runlog::MvState::clamped_low || st == runlog::MvState::clamped_high) {
          row.flags |= runlog::kClamped;
        }
      }
    }
    if (const auto s = writer.write_row(row); s != runlog::WriteStatus::ok) fail(s);
  }
  file.commit();
}

}  // namespace excite::host
