// SPDX-License-Identifier: MIT
#include "host/adaptive/scale_plan.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "host/adaptive/cv_limit_text.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/table.hpp"
#include "host/export/model_file.hpp"
#include "host/identify/run_data.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/output/input_path.hpp"

namespace excite::host {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// `what` at `sample_time_min` must run at the model's.
void require_sample_time(const std::string& what, double sample_time_min, double model_min) {
  if (std::abs(sample_time_min - model_min) <= 1e-9 * model_min) return;
  char text[200];
  std::snprintf(text, sizeof text, ": sample time = %g min, expected %g min (the model's)",
                sample_time_min, model_min);
  throw std::invalid_argument(what + text);
}

// The runs' input deviations, one after the other (the excitation already applied).
Eigen::MatrixXd history_of(const ScalePlanRequest& request, const ModelChannels& channels,
                           const IdentifiedModel& model) {
  Eigen::MatrixXd history(0, model.inputs);
  for (const std::string& path : request.history) {
    refuse_directory(path, "a run log (CSV)");
    runlog::ReadResult read = runlog::read_run_log(path, limited_read_options());
    if (!read.ok()) throw std::invalid_argument(read.error->to_string());
    const RunData data = run_data(read.log);
    check_same_channels(channels, request.model.string(), read.log.input_names,
                        read.log.output_names, path);
    require_sample_time(path, data.sample_time_min, model.sample_time_min);
    Eigen::MatrixXd longer(history.rows() + data.U.rows(), model.inputs);
    longer << history, data.U;
    history = std::move(longer);
  }
  return history;
}

}  // namespace

ScaledPlan scale_plan(const ScalePlanRequest& request) {
  ModelChannels channels;
  const IdentifiedModel model = read_model_file(request.model, &channels);
  const auto next = read_plan_file(request.plan);
  if (static_cast<int>(next->recipe.channels) != model.inputs) {
    std::vector<std::string> plan_channels;
    for (std::uint32_t c = 0; c < next->recipe.channels; ++c)
      plan_channels.emplace_back(plan::text_of(next->meta.channels[c].name));
    throw std::invalid_argument(
        request.plan.string() + ": channels = " + std::to_string(next->recipe.channels) + " (" +
        joined(plan_channels) + "), expected " + std::to_string(model.inputs) + " (the inputs of " +
        request.model.string() + ": " + joined(channels.inputs) + ")");
  }
  require_sample_time(request.plan.string(), next->meta.sample_time_min, model.sample_time_min);
  const Eigen::MatrixXd segment = make_table(next->recipe);
  const Eigen::MatrixXd history = history_of(request, channels, model);

  const CvLimits limits = parse_cv_limits(request.limits, channels.outputs, "the model's");
  ScaledPlan out;
  out.scale = scale_segment(model, history, segment, limits, request.options);
  if (out.scale.binding_output >= 0)
    out.binding_output = channels.outputs[static_cast<std::size_t>(out.scale.binding_output)];
  out.sample_time_min = model.sample_time_min;
  out.history_rows = static_cast<long long>(history.rows());
  if (!(out.scale.scale > 0.0)) return out;
  plan::Plan scaled = *next;
  for (auto& row : scaled.recipe.mix) {
    for (double& m : row) m *= out.scale.scale;
  }
  char note[plan::kProvenanceCapacity];
  std::snprintf(note, sizeof note, "%s; scaled %.6g (excite scale)",
                std::string(plan::text_of(next->meta.provenance)).c_str(), out.scale.scale);
  if (!plan::set_text(scaled.meta.provenance, note)) {
    std::snprintf(note, sizeof note, "scaled %.6g (excite scale)", out.scale.scale);
    plan::set_text(scaled.meta.provenance, note);
  }
  out.plan = std::move(scaled);
  return out;
}

}  // namespace excite::host
