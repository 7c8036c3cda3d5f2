// SPDX-License-Identifier: MIT
// excite scale NEXT.plan --model MODEL.json --limit CV=LOW:HIGH … [--history RUN.csv …]
//              [--k-sigma 2] -o SCALED.plan [--json]
// Predictive amplitude control (issue 26 §2, host/adaptive/README.md): the next segment's
// scale so every CV's predicted excursion ± k σ stays inside its test limits; the plan is
// written with its mixing matrix (hence every value of its table) multiplied by that scale.

#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>
#include <stdexcept>

#include "host/adaptive/scale_plan.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/design/plan_file.hpp"

namespace excite::host::cli {
namespace {

struct ScaleCommandOptions {
  std::string plan_path;
  std::string model_path;
  std::vector<std::string> limits;
  std::vector<std::string> history;
  std::string output;
  double k_sigma = 2.0;
  bool json = false;
};

// Options → one call (host/adaptive/scale_plan.hpp) → the scale said, the plan written.
void run(const ScaleCommandOptions& opt) {
  std::vector<std::string> inputs = {opt.plan_path, opt.model_path};
  inputs.insert(inputs.end(), opt.history.begin(), opt.history.end());
  refuse_output_among_inputs(opt.output, inputs);
  ScalePlanRequest request{opt.plan_path, opt.model_path, opt.history, opt.limits, {}};
  request.options.k_sigma = opt.k_sigma;
  const ScaledPlan scaled = scale_plan(request);
  const SegmentScale& s = scaled.scale;
  if (opt.json) {
    nlohmann::json j = {
        {"scale", s.scale},
        {"k_sigma", opt.k_sigma},
        {"binding_output",
         s.binding_output >= 0 ? nlohmann::json(scaled.binding_output) : nlohmann::json(nullptr)},
        {"binding_row",
         s.binding_row >= 0 ? nlohmann::json(s.binding_row) : nlohmann::json(nullptr)},
        {"binding_limit", s.binding_output >= 0 ? nlohmann::json(s.binding_high ? "high" : "low")
                                                : nlohmann::json(nullptr)},
        {"reason", s.reason},
        {"history_rows", scaled.history_rows},
        {"plan", opt.output}};
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << "scale " << s.scale;
    if (s.scale > 0.0 && s.binding_output >= 0) {
      std::cout << ": " << scaled.binding_output << " reaches its "
                << (s.binding_high ? "high" : "low") << " limit at row " << s.binding_row
                << " of the segment (t = "
                << static_cast<double>(s.binding_row) * scaled.sample_time_min
                << " min), prediction ± " << opt.k_sigma << " sigma";
    }
    std::cout << '\n';
  }
  if (!scaled.plan) {
    throw std::runtime_error("no plan written: the scale is 0 (" + s.reason + ")");
  }
  write_plan_file(*scaled.plan, opt.output);
  if (!opt.json) std::cout << "wrote " << opt.output << '\n';
}

}  // namespace

void add_scale_command(CLI::App& app) {
  auto opt = std::make_shared<ScaleCommandOptions>();
  CLI::App* cmd = app.add_subcommand(
      "scale",
      "Scale the next segment so every CV's predicted excursion ± k sigma stays inside its test "
      "limits (predictive amplitude control); write the scaled plan");
  cmd->add_option("plan", opt->plan_path, "the next segment's plan file")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--model", opt->model_path, "the current model (excite identify -o)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--limit", opt->limits,
                  "a CV's test limits as deviations from its baseline: CV=LOW:HIGH (repeat; a CV "
                  "without one is not limited)")
      ->required();
  cmd->add_option("--history", opt->history,
                  "run logs of the excitation already applied, in order (its response still "
                  "coming is predicted too)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--k-sigma", opt->k_sigma, "the band the limits must hold: prediction ± k sigma")
      ->capture_default_str()
      ->check(finite_non_negative());
  cmd->add_option("-o,--output", opt->output, "the scaled plan")->required();
  cmd->add_flag("--json", opt->json, "machine-readable output");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
