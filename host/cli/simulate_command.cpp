// SPDX-License-Identifier: MIT
// excite simulate PLAN --plant NAME [--noise-var V] [--seed S] [--periods K] -o RUN.csv
// excite simulate --plant NAME --step INPUT=AMPL [--samples N] [--sample-time-min T] [-o RUN.csv]
// --plant MODEL.json: an identified model (excite identify -o) stands in for the plant.
// excite simulate PLAN --plant NAME --controller FILE.toml [--excitation setpoint|mv]
//                 [--dither-unknown] [--disturbance-std S --disturbance-tau-min TAU] -o RUN.csv
//   closed loop in process (host/simulate/closed_loop.hpp): the plan's table is r, added to
//   the CV setpoints (its channels = the plant's outputs) or to the controller's MV output
//   (= its inputs); the log is run-log v4.

#include <cmath>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "firmware/runlog/format.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/table.hpp"
#include "host/export/model_file.hpp"
#include "host/export/model_plant.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/output/text_table.hpp"
#include "host/simulate/closed_loop.hpp"
#include "host/simulate/simulate.hpp"
#include "sim/control/controller_file.hpp"
#include "sim/control/make_controller.hpp"

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
  std::string controller;  // a controller file: run closed loop
  std::string excitation = "setpoint";
  bool dither_unknown = false;
  bool excitation_given = false;
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

// The plan's table as r, played `periods` times.
Eigen::MatrixXd plan_signal(const plan::Plan& p, std::uint32_t periods) {
  const Table table = make_table(p.recipe);
  Eigen::MatrixXd r(table.rows() * static_cast<Eigen::Index>(periods), table.cols());
  for (std::uint32_t k = 0; k < periods; ++k) r.middleRows(k * table.rows(), table.rows()) = table;
  return r;
}

SimulatedRun run_closed_loop(const SimulateOptions& opt, sim::Plant& plant) {
  if (opt.plan_path.empty() || opt.output.empty()) {
    throw std::invalid_argument("--controller = " + opt.controller +
                                " with no PLAN or -o RUN.csv, expected both (a closed-loop run)");
  }
  const sim::control::ControllerFile file = sim::control::load_controller_file(opt.controller);
  std::unique_ptr<sim::Plant> model = file.model.model_file.empty()
                                          ? sim::control::load_model(file)
                                          : plant_named(file.model.model_file);
  const Eigen::MatrixXd g0 = plant.static_gain();
  const auto controller = sim::control::make_controller(file, *model, &g0);
  const auto p = read_plan_file(opt.plan_path);
  ClosedLoopOptions loop;
  // A closed-loop plan (version 4) says where r goes; an open-loop plan takes --excitation.
  const plan::Excitation planned = p->meta.excitation;
  if (planned != plan::Excitation::open_loop && opt.excitation_given &&
      opt.excitation != plan::to_text(planned)) {
    throw std::invalid_argument("--excitation = " + opt.excitation + ", expected " +
                                plan::to_text(planned) + " as the plan " + opt.plan_path +
                                " says (or leave it out)");
  }
  const bool mv = planned == plan::Excitation::mv ||
                  (planned == plan::Excitation::open_loop && opt.excitation == "mv");
  loop.excitation = mv ? runlog::Excitation::mv : runlog::Excitation::setpoint;
  loop.dither_known = !opt.dither_unknown;
  set_controller(loop, file, opt.controller);
  if (opt.sim.periods == 0 ||
      std::uint64_t{opt.sim.periods} * p->recipe.samples > kMaxSimulatedRows) {
    throw std::invalid_argument("--periods x plan samples = " + std::to_string(opt.sim.periods) +
                                " x " + std::to_string(p->recipe.samples) + ", expected 1 to " +
                                std::to_string(kMaxSimulatedRows) + " rows");
  }
  SimulatedRun run =
      simulate_closed_loop(plan_signal(*p, opt.sim.periods), opt.plan_path, p->meta.sample_time_min,
                           plant, *controller, loop, opt.sim);
  run.time_scales = {p->meta.tau_high_min, p->meta.beta, p->meta.switch_time_min};
  return run;
}

void run(const SimulateOptions& opt) {
  refuse_output_among_inputs(opt.output, {opt.plan_path, opt.plant, opt.controller});
  const HumanTextAside aside(opt.output);
  const auto plant = plant_named(opt.plant);
  SimulatedRun result;
  if (!opt.controller.empty()) {
    if (!opt.step.empty())
      throw std::invalid_argument("--step with --controller, expected a PLAN for a closed loop");
    result = run_closed_loop(opt, *plant);
  } else if (!opt.step.empty()) {
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
    if (std::fabs(amplitude) > kMaxRunValue) {  // the run log's value limit (run_log_limits.hpp)
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
    if (p->meta.excitation != plan::Excitation::open_loop) {
      throw std::invalid_argument(opt.plan_path +
                                  ": excitation = " + plan::to_text(p->meta.excitation) +
                                  " (a closed-loop plan), expected --controller FILE to run it "
                                  "under");
    }
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
  cmd->add_option("--disturbance-std", opt->sim.disturbance_std,
                  "coloured output disturbance: stationary standard deviation per output "
                  "(first-order filtered noise, sim/lti/disturbance.hpp; 0: none)")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("--disturbance-tau-min", opt->sim.disturbance_tau_min,
                  "the disturbance filter's time constant, minutes (of the order of the plant's)")
      ->check(finite_positive());
  cmd->add_option("--controller", opt->controller,
                  "run closed loop under this controller file (sim/control/README.md): the "
                  "plan's table is r; writes run-log v4")
      ->check(CLI::ExistingFile);
  cmd->add_option("--excitation", opt->excitation,
                  "closed loop: r added to the CV setpoints (setpoint; plan channels = outputs) "
                  "or to the controller's MV output as a dither (mv; = inputs)")
      ->capture_default_str()
      ->check(CLI::IsMember({"setpoint", "mv"}));
  cmd->add_flag("--dither-unknown", opt->dither_unknown,
                "closed loop, mv: the controller is not told of the dither (by default it is, "
                "as a known move)");
  cmd->callback([opt, cmd] {
    opt->excitation_given = cmd->count("--excitation") > 0;
    if (opt->sim.disturbance_std > 0.0 && opt->sim.disturbance_tau_min <= 0.0) {
      throw std::invalid_argument(
          "--disturbance-tau-min = (not given), expected a time "
          "constant in minutes with --disturbance-std > 0");
    }
    run(*opt);
  });
}

}  // namespace excite::host::cli
