// SPDX-License-Identifier: MIT
// excite scale NEXT.plan --model MODEL.json --limit CV=LOW:HIGH … [--history RUN.csv …]
//              [--k-sigma 2] -o SCALED.plan [--json]
// Predictive amplitude control (issue 26 §2, host/adaptive/README.md): the next segment's
// scale so every CV's predicted excursion ± k σ stays inside its test limits; the plan is
// written with its mixing matrix (hence every value of its table) multiplied by that scale.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "firmware/plan/plan.hpp"
#include "host/adaptive/amplitude_control.hpp"
#include "host/adaptive/cv_limit_text.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/cli/run_input.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/table.hpp"
#include "host/export/model_file.hpp"

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

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

void run(const ScaleCommandOptions& opt) {
  std::vector<std::string> inputs = {opt.plan_path, opt.model_path};
  inputs.insert(inputs.end(), opt.history.begin(), opt.history.end());
  refuse_output_among_inputs(opt.output, inputs);
  ModelChannels channels;
  const IdentifiedModel model = read_model_file(opt.model_path, &channels);
  const auto next = read_plan_file(opt.plan_path);
  // The plan's channels drive the model's inputs in order (as the gateway maps them onto its
  // setpoints: by position; a plan names its channels by the design, a run log by the plant),
  // at the model's sample time.
  if (static_cast<int>(next->recipe.channels) != model.inputs) {
    std::vector<std::string> plan_channels;
    for (std::uint32_t c = 0; c < next->recipe.channels; ++c)
      plan_channels.emplace_back(plan::text_of(next->meta.channels[c].name));
    throw std::invalid_argument(
        opt.plan_path + ": channels = " + std::to_string(next->recipe.channels) + " (" +
        joined(plan_channels) + "), expected " + std::to_string(model.inputs) + " (the inputs of " +
        opt.model_path + ": " + joined(channels.inputs) + ")");
  }
  if (std::abs(next->meta.sample_time_min - model.sample_time_min) > 1e-9 * model.sample_time_min) {
    char text[200];
    std::snprintf(text, sizeof text, ": sample time = %g min, expected %g min (the model's)",
                  next->meta.sample_time_min, model.sample_time_min);
    throw std::invalid_argument(opt.plan_path + text);
  }
  const Table table = make_table(next->recipe);
  const Eigen::MatrixXd segment = table;

  // The history: the runs' input deviations, one after the other, at the model's sample time.
  Eigen::MatrixXd history(0, model.inputs);
  for (const std::string& path : opt.history) {
    const Run r = read_run(path);
    check_same_channels(channels, opt.model_path, r.log.input_names, r.log.output_names, path);
    if (std::abs(r.data.sample_time_min - model.sample_time_min) > 1e-9 * model.sample_time_min) {
      char text[200];
      std::snprintf(text, sizeof text, ": sample time = %g min, expected %g min (the model's)",
                    r.data.sample_time_min, model.sample_time_min);
      throw std::invalid_argument(path + text);
    }
    Eigen::MatrixXd longer(history.rows() + r.data.U.rows(), model.inputs);
    longer << history, r.data.U;
    history = std::move(longer);
  }

  const CvLimits limits = parse_cv_limits(opt.limits, channels.outputs, "the model's");
  ScaleOptions options;
  options.k_sigma = opt.k_sigma;
  const SegmentScale s = scale_segment(model, history, segment, limits, options);
  const std::string binding =
      s.binding_output >= 0 ? channels.outputs[static_cast<std::size_t>(s.binding_output)] : "";

  if (opt.json) {
    nlohmann::json j = {
        {"scale", s.scale},
        {"k_sigma", opt.k_sigma},
        {"binding_output",
         s.binding_output >= 0 ? nlohmann::json(binding) : nlohmann::json(nullptr)},
        {"binding_row",
         s.binding_row >= 0 ? nlohmann::json(s.binding_row) : nlohmann::json(nullptr)},
        {"binding_limit", s.binding_output >= 0 ? nlohmann::json(s.binding_high ? "high" : "low")
                                                : nlohmann::json(nullptr)},
        {"reason", s.reason},
        {"history_rows", history.rows()},
        {"plan", opt.output}};
    std::cout << j.dump(2) << '\n';
  } else {
    std::cout << "scale " << s.scale;
    if (s.scale > 0.0 && s.binding_output >= 0) {
      std::cout << ": " << binding << " reaches its " << (s.binding_high ? "high" : "low")
                << " limit at row " << s.binding_row << " of the segment (t = "
                << static_cast<double>(s.binding_row) * model.sample_time_min
                << " min), prediction ± " << opt.k_sigma << " sigma";
    }
    std::cout << '\n';
  }
  if (!(s.scale > 0.0)) {
    throw std::runtime_error("no plan written: the scale is 0 (" + s.reason + ")");
  }
  plan::Plan scaled = *next;
  for (auto& row : scaled.recipe.mix) {
    for (double& m : row) m *= s.scale;
  }
  char note[plan::kProvenanceCapacity];
  std::snprintf(note, sizeof note, "%s; scaled %.6g (excite scale)",
                std::string(plan::text_of(next->meta.provenance)).c_str(), s.scale);
  if (!plan::set_text(scaled.meta.provenance, note)) {
    std::snprintf(note, sizeof note, "scaled %.6g (excite scale)", s.scale);
    plan::set_text(scaled.meta.provenance, note);
  }
  write_plan_file(scaled, opt.output);
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
