// SPDX-License-Identifier: MIT
// excite simulate PLAN --plant NAME [--noise-var V] [--seed S] [--periods K] -o RUN.csv
// excite simulate --plant NAME --step INPUT=AMPL [--samples N] [--sample-time-min T] [-o RUN.csv]
// --plant MODEL.json: an identified model (excite identify -o) stands in for the plant.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "firmware/runlog/format.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/cli/run_input.hpp"
#include "host/cli/text_table.hpp"
#include "host/design/plan_file.hpp"
#include "host/export/model_file.hpp"
#include "host/export/model_plant.hpp"
#include "host/simulate/simulate.hpp"

namespace excite::host::cli {
namespace {

struct SimulateOptions {
  std::string plan_path;
  std::string plant;
  std::string step;
  std::string output;
  SimulationOptions sim;
  std::uint32_t samples = 600;
  double sample_time_min = 1.0;
};

// A quick look at a step response: twenty rows of the outputs.
void print_step(const SimulatedRun& run) {
  std::vector<std::string> header{"t [min]"};
  for (const std::string& name : run.output_names) header.push_back("d" + name);
  TextTable table(header);
  const Eigen::Index every = std::max<Eigen::Index>(1, run.dy.rows() / 20);
  for (Eigen::Index k = 0; k < run.dy.rows(); k += every) {
    std::vector<std::string> row{num(static_cast<double>(k) * run.sample_time_min, 5)};
    for (Eigen::Index i = 0; i < run.dy.cols(); ++i) row.push_back(num(run.dy(k, i), 5));
    table.add_row(row);
  }
  std::cout << run.plant << ": " << run.plan << '\n';
  table.print(std::cout);
}

// A library plant, a plant file NAME.toml, or an identified model MODEL.json.
std::unique_ptr<sim::Plant> plant_named(const std::string& name) {
  if (name.ends_with(".json")) return plant_from_model(read_named_model_file(name));
  return sim::make_plant(name);
}

void run(const SimulateOptions& opt) {
  refuse_output_among_inputs(opt.output, {opt.plan_path, opt.plant});
  const HumanTextAside aside(opt.output);
  const auto plant = plant_named(opt.plant);
  SimulatedRun result;
  if (!opt.step.empty()) {
    if (!opt.plan_path.empty())
      throw std::invalid_argument("give either PLAN or --step INPUT=AMPL, not both");
    const auto eq = opt.step.find('=');
    if (eq == std::string::npos) {
      throw std::invalid_argument("--step \"" + opt.step +
                                  "\", expected INPUT=AMPLITUDE, e.g. L=0.01");
    }
    std::size_t used = 0;
    double amplitude = 0.0;
    try {
      amplitude = std::stod(opt.step.substr(eq + 1), &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || eq + 1 + used != opt.step.size() || !std::isfinite(amplitude)) {
      throw std::invalid_argument("--step \"" + opt.step +
                                  "\": the amplitude is not a finite number");
    }
    if (std::fabs(amplitude) > kMaxRunValue) {  // the run log's value limit (run_input.hpp)
      char text[160];
      std::snprintf(text, sizeof text, "--step: amplitude = %g, expected |amplitude| <= %g",
                    amplitude, kMaxRunValue);
      throw std::invalid_argument(std::string(text) + " (a run's value limit, host/README.md)");
    }
    result = simulate_step(*plant, opt.step.substr(0, eq), amplitude, opt.samples,
                           opt.sample_time_min, opt.sim);
    print_step(result);
  } else {
    if (opt.plan_path.empty() || opt.output.empty()) {
      throw std::invalid_argument("give PLAN and -o RUN.csv, or --step INPUT=AMPL");
    }
    const auto p = read_plan_file(opt.plan_path);
    result = simulate_plan(*p, opt.plan_path, *plant, opt.sim);
  }
  if (!opt.output.empty()) {
    result.producer = "excite simulate " + std::string(runlog::kVersion);
    write_run_log(result, opt.output);
    std::cout << "wrote " << opt.output << ": " << result.du.rows() << " samples of "
              << result.sample_time_min << " min, " << result.input_names.size() << " inputs, "
              << result.output_names.size() << " outputs\n";
  }
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate", "Run a plan (or a step) open loop on a simulated plant; write the run log");
  cmd->add_option("plan", opt->plan_path, "plan file")->check(CLI::ExistingFile);
  cmd->add_option("--plant", opt->plant,
                  "library plant, colaA, pilot15, a plant file NAME.toml, or an identified model "
                  "MODEL.json (excite identify -o)")
      ->required();
  cmd->add_option("--noise-var", opt->sim.noise_variance, "measurement noise variance per output")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--seed", opt->sim.seed, "noise seed")->capture_default_str();
  cmd->add_option("--periods", opt->sim.periods, "play the table this many times")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--step", opt->step, "step response instead of a plan: INPUT=AMPLITUDE");
  cmd->add_option("--samples", opt->samples, "step response length")
      ->capture_default_str()
      ->check(CLI::Range(std::uint32_t{2}, static_cast<std::uint32_t>(kMaxSimulatedRows)));
  cmd->add_option("--sample-time-min", opt->sample_time_min, "step response sample time")
      ->capture_default_str()
      ->check(finite_positive());
  cmd->add_option("-o,--output", opt->output, "run log (CSV, firmware/runlog/README.md)");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
