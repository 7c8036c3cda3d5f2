// SPDX-License-Identifier: MIT
// excite export MODEL.json --format step-csv|matlab|python-control|json [--horizon N] -o FILE
// An identified model (excite identify -o) for other tools: the step table of a DMC-style
// controller, a MATLAB/Octave or python-control script, a tool-neutral JSON (host/export).

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "host/cli/commands.hpp"
#include "host/cli/output_target.hpp"
#include "host/export/formats.hpp"
#include "host/export/model_file.hpp"
#include "host/export/step_response.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::cli {
namespace {

enum class ExportFormat { step_csv, matlab, python_control, json };

struct ExportOptions {
  std::string model;
  ExportFormat format = ExportFormat::json;
  bool bands = false;
  int horizon = 0;  // samples; 0: until every element has settled (settling_samples)
  std::string output;
};

constexpr int kMaxHorizon = 1 << 20;  // the --horizon range's top

// step-csv without --horizon: until the slowest element has settled, within the --horizon
// range; beyond it the element is named (a Tp of 1e9 min once wrapped to a one-row table).
int default_horizon(const NamedModel& m, const std::string& path) {
  const Settling s = slowest_settling(m.model);
  if (s.samples <= kMaxHorizon) return static_cast<int>(s.samples);
  const ElementEstimate& e = m.model.element(s.output, s.input);
  char text[200];
  std::snprintf(text, sizeof text,
                "settling time Td + 7 (Tp1 + Tp2 + Tn/zeta + |Tz|) = %.6g min = %.6g samples of "
                "%g min, expected at most %d samples (the --horizon range; give --horizon N)",
                settling_time_min(e.value), s.samples, m.model.sample_time_min, kMaxHorizon);
  throw std::invalid_argument(path + ": element " +
                              m.outputs.at(static_cast<std::size_t>(s.output)) + " <- " +
                              m.inputs.at(static_cast<std::size_t>(s.input)) + ": " + text);
}

void run(const ExportOptions& opt) {
  refuse_output_among_inputs(opt.output, {opt.model});
  const HumanTextAside aside(opt.output);
  const NamedModel m = read_named_model_file(opt.model);
  std::string text;
  std::string what;
  switch (opt.format) {
    case ExportFormat::step_csv: {
      const int horizon = opt.horizon > 0 ? opt.horizon : default_horizon(m, opt.model);
      text = step_csv(m, horizon, opt.bands);
      std::ostringstream text_of;
      text_of << "step coefficients, " << horizon << " samples of " << m.model.sample_time_min
              << " min";
      what = text_of.str();
      break;
    }
    case ExportFormat::matlab:
      text = matlab_script(m);
      what = "MATLAB/Octave script (tf array G)";
      break;
    case ExportFormat::python_control:
      text = python_control_script(m);
      what = "python-control script (G, DELAYS_MIN, with_pade)";
      break;
    case ExportFormat::json:
      text = transfer_json(m);
      what = "transfer-matrix JSON";
      break;
  }
  write_whole_file(opt.output, text);
  std::cout << "wrote " << opt.output << ": " << what << ", " << m.outputs.size() << " CVs x "
            << m.inputs.size() << " MVs\n";
}

}  // namespace

void add_export_command(CLI::App& app) {
  auto opt = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export",
      "An identified model for other tools: DMC step table, MATLAB, python-control, JSON");
  cmd->add_option("model", opt->model, "model file (excite identify -o)")
      ->required()
      ->check(CLI::ExistingFile);
  const std::map<std::string, ExportFormat> formats = {
      {"step-csv", ExportFormat::step_csv},
      {"matlab", ExportFormat::matlab},
      {"python-control", ExportFormat::python_control},
      {"json", ExportFormat::json}};
  cmd->add_option("--format", opt->format, "step-csv | matlab | python-control | json")
      ->required()
      ->transform(CLI::CheckedTransformer(formats, CLI::ignore_case));
  cmd->add_option("--horizon", opt->horizon,
                  "step-csv: coefficients (samples; default: until every element has settled "
                  "to 0.1 %)")
      ->check(CLI::Range(1, kMaxHorizon));
  cmd->add_flag("--bands", opt->bands,
                "step-csv: each element's -2s and +2s columns (from the model file's covariance)");
  cmd->add_option("-o,--output", opt->output, "file to write")->required();
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
