// SPDX-License-Identifier: MIT
// excite identify RUN.csv [--json] [-o MODEL] [--max-delay MIN] [--max-time-constant MIN]
//                         [--tau-high MIN] [--beta B] [--threads N]
// (6.1.1) models per output, fit % (5.5.1), identified G(0) and its directions.
// Time constants are bounded above by β·τ_H (SPEC §6): --max-time-constant if given, else
// --beta·--tau-high, else the case study of the run log's plant, else the run's length.

#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/model_file.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/run_input.hpp"
#include "host/cli/text_table.hpp"
#include "host/cli/time_constant_bound.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::cli {
namespace {

struct IdentifyCommandOptions {
  std::string run_path;
  std::string model_path;
  bool json = false;
  TimeConstantBoundOptions bound;
  IdentifyOptions identify;
};

void print(const IdentificationResult& r, const Run& run) {
  const IdentifiedModel& m = r.model;
  for (int o = 0; o < m.outputs; ++o) {
    std::cout << "output " << run.log.output_names[static_cast<std::size_t>(o)]
              << ": fit = " << num(r.fits[static_cast<std::size_t>(o)].fit_percent) << " %\n";
    TextTable t(
        {"input", "K", "+-", "Td [min]", "+-", "Tp1 [min]", "+-", "Tp2 [min]", "+-", "status"});
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      std::string status = to_string(e.status);
      if (!e.reason.empty()) status += ": " + e.reason;
      t.add_row({run.log.input_names[static_cast<std::size_t>(i)], num(e.value.gain),
                 num(e.std_error.gain), num(e.value.delay_min), num(e.std_error.delay_min),
                 num(e.value.tau1_min), num(e.std_error.tau1_min), num(e.value.tau2_min),
                 num(e.std_error.tau2_min), status});
    }
    t.print(std::cout);
    std::cout << '\n';
  }
  if (r.gain) {
    std::cout << "identified G(0): singular values";
    for (Eigen::Index i = 0; i < r.gain->singular_values.size(); ++i) {
      std::cout << ' ' << num(r.gain->singular_values(i), 5);
    }
    std::cout << ", condition number " << num(r.gain->condition_number, 5) << '\n';
  } else {
    std::cout << "identified G(0): " << r.gain_unavailable_reason << '\n';
  }
}

void run(const IdentifyCommandOptions& opt) {
  const Run data = read_run(opt.run_path);
  IdentifyOptions options = opt.identify;
  const auto [bound, source] = time_constant_bound(opt.bound, data.log.plant);
  options.max_time_constant_min = bound;
  const IdentificationResult result =
      identify(data.data.U, data.data.Y, data.data.sample_time_min, options);
  const nlohmann::json j = model_json(result, data.log.input_names, data.log.output_names);
  if (!opt.model_path.empty()) {
    write_whole_file(opt.model_path, j.dump(2) + '\n');
  }
  if (opt.json) {
    std::cout << j.dump(2) << '\n';
  } else {
    const double shown =
        bound > 0.0 ? bound : static_cast<double>(data.data.U.rows()) * data.data.sample_time_min;
    std::cout << "time constants bounded by " << num(shown) << " min (" << source << ")\n\n";
    print(result, data);
  }
}

}  // namespace

void add_identify_command(CLI::App& app) {
  auto opt = std::make_shared<IdentifyCommandOptions>();
  CLI::App* cmd =
      app.add_subcommand("identify", "Identify two-pole-plus-delay models (6.1.1) from a run log");
  cmd->add_option("run", opt->run_path, "run log (CSV)")->required();
  cmd->add_option("-o,--output", opt->model_path, "write the model file (JSON)");
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->add_option("--max-delay", opt->identify.max_delay_min, "upper bound of every delay, min")
      ->capture_default_str()
      ->check(
          finite_number(0.0, true, "a finite number of minutes > 0 (0 leaves no delay to fit)"));
  add_time_constant_bound_options(cmd, opt->bound);
  cmd->add_option("--threads", opt->identify.threads, "outputs fitted in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 64));
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
