// SPDX-License-Identifier: MIT
#include "host/cli/model_file.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "host/cli/input_path.hpp"
#include "host/cli/json_file.hpp"
#include "host/cli/json_util.hpp"

namespace excite::host::cli {
namespace {

constexpr const char* kFormat = "excite model v1";

nlohmann::json parameters(const TwoPoleDelay& p) {
  return {{"K", to_json(p.gain)},
          {"Tp1", to_json(p.tau1_min)},
          {"Tp2", to_json(p.tau2_min)},
          {"Td", to_json(p.delay_min)}};
}

// A value in short form for a message: at most 40 characters of its JSON text.
std::string shown(const nlohmann::json& v) {
  const std::string text = v.dump();
  return text.size() > 40 ? text.substr(0, 40) + "…" : text;
}

// `where` is "FILE: outputs[0].elements[1]" (or "FILE:" at the top): the field's name.
std::string field(const std::string& where, const char* key) {
  return where.back() == ':' ? where + " " + key : where + "." + key;
}

double number(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw std::invalid_argument(field(where, key) + " = (missing), expected a number");
  const nlohmann::json& v = j.at(key);
  if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
  if (!v.is_number())
    throw std::invalid_argument(field(where, key) + " = " + shown(v) + ", expected a number");
  return v.get<double>();
}

// An optional string field ("" when absent or null).
std::string text(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.is_object() || !j.contains(key) || j.at(key).is_null()) return "";
  const nlohmann::json& v = j.at(key);
  if (!v.is_string())
    throw std::invalid_argument(field(where, key) + " = " + shown(v) + ", expected a string");
  return v.get<std::string>();
}

}  // namespace

nlohmann::json model_json(const IdentificationResult& result,
                          const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names) {
  const IdentifiedModel& m = result.model;
  nlohmann::json outputs = nlohmann::json::array();
  for (int o = 0; o < m.outputs; ++o) {
    nlohmann::json elements = nlohmann::json::array();
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      nlohmann::json j = parameters(e.value);
      j["input"] = input_names.at(static_cast<std::size_t>(i));
      j["se"] = parameters(e.std_error);
      j["status"] = to_string(e.status);
      j["reason"] = e.reason;
      j["on_bound"] = e.on_bound();
      j["grade"] = to_string(e.grade);
      j["grade_reason"] = e.grade_reason;
      elements.push_back(j);
    }
    const OutputFit& fit = result.fits.at(static_cast<std::size_t>(o));
    const ResidualTests& t = fit.residual_tests;
    nlohmann::json out = {{"name", output_names.at(static_cast<std::size_t>(o))},
                          {"fit", to_json(fit.fit_percent)},
                          {"elements", elements}};
    if (t.lags > 0) {
      out["residual_tests"] = {{"lags", t.lags},
                               {"whiteness", to_json(t.whiteness)},
                               {"whiteness_limit_99", to_json(t.whiteness_limit)},
                               {"independence", to_json(t.independence)},
                               {"independence_limit_99", to_json(t.independence_limit)}};
    }
    if (static_cast<std::size_t>(o) < m.gain_covariance.size()) {
      out["gain_covariance"] = rows_to_json(m.gain_covariance[static_cast<std::size_t>(o)]);
    }
    outputs.push_back(out);
  }
  nlohmann::json j = {{"format", kFormat},
                      {"sample_time_min", m.sample_time_min},
                      {"inputs", input_names},
                      {"outputs", outputs},
                      {"gain", rows_to_json(m.static_gain())}};
  if (result.gain) {
    j["singular_values"] = to_json(result.gain->singular_values);
    j["condition_number"] = to_json(result.gain->condition_number);
    j["xi"] = to_json(result.gain->xi);
    j["rga"] = rows_to_json(result.gain->rga);
    if (const auto& u = result.gain_uncertainty) {
      nlohmann::json minors = nlohmann::json::array();
      for (const PrincipalMinor& pm : u->principal_minors) {
        minors.push_back({{"rows", pm.rows},
                          {"value", to_json(pm.value)},
                          {"se", to_json(pm.std_error)},
                          {"sign_uncertain", pm.sign_uncertain}});
      }
      j["gain_uncertainty"] = {{"singular_value_se", to_json(u->singular_value_se)},
                               {"input_angle_se_deg", to_json(u->input_angle_se_deg)},
                               {"output_angle_se_deg", to_json(u->output_angle_se_deg)},
                               {"principal_minors", minors},
                               {"sign_uncertain_minors", u->sign_uncertain_minors}};
    }
  } else {
    j["singular_values"] = nullptr;
    j["condition_number"] = nullptr;
    j["gain_unavailable_reason"] = result.gain_unavailable_reason;
  }
  return j;
}

IdentifiedModel read_model_file(const std::filesystem::path& path, ModelChannels* channels) {
  NamedModel named = read_named_model_file(path);
  if (channels != nullptr) {
    channels->inputs = named.inputs;
    channels->outputs = named.outputs;
  }
  return std::move(named.model);
}

NamedModel read_named_model_file(const std::filesystem::path& path) {
  const std::string where = path.string();
  refuse_directory(path, "a model file (excite identify -o)");
  const nlohmann::json j = read_json_file(where, "a model file from excite identify -o");
  if (!j.is_object() || !j.contains("format") || j["format"] != kFormat) {
    throw std::invalid_argument(where + ": format: expected \"" + kFormat +
                                "\" (a file from excite identify -o)");
  }
  NamedModel named;
  named.source = where;
  IdentifiedModel& m = named.model;
  m.sample_time_min = number(j, "sample_time_min", where + ":");
  if (!(m.sample_time_min > 0.0))
    throw std::invalid_argument(where + ": sample_time_min: expected > 0");
  for (const char* key : {"inputs", "outputs"}) {
    if (!j.contains(key) || !j[key].is_array()) {
      throw std::invalid_argument(where + ": " + key + " = " +
                                  (j.contains(key) ? shown(j[key]) : "(missing)") +
                                  ", expected an array");
    }
    // Sizes before any allocation: a 256 KB file once asked for 36 M elements (8.8 GB).
    if (j[key].empty() || j[key].size() > kMaxModelChannels) {
      throw std::invalid_argument(where + ": " + key + " = " + std::to_string(j[key].size()) +
                                  " channels, expected 1 to " + std::to_string(kMaxModelChannels) +
                                  " (host/README.md, Limits)");
    }
  }
  for (const auto& [key, names] :
       {std::pair{"inputs", &named.inputs}, std::pair{"outputs", &named.outputs}}) {
    for (std::size_t k = 0; k < j[key].size(); ++k) {
      const nlohmann::json& e = j[key][k];
      const nlohmann::json* name =
          e.is_string() ? &e : (e.is_object() && e.contains("name") ? &e["name"] : nullptr);
      if (name == nullptr || !name->is_string()) {
        throw std::invalid_argument(where + ": " + key + "[" + std::to_string(k) +
                                    "]: expected a channel name");
      }
      names->push_back(name->get<std::string>());
    }
  }
  m.inputs = static_cast<int>(j["inputs"].size());
  m.outputs = static_cast<int>(j["outputs"].size());
  m.elements.resize(static_cast<std::size_t>(m.inputs * m.outputs));
  for (int o = 0; o < m.outputs; ++o) {
    const nlohmann::json& out = j["outputs"][static_cast<std::size_t>(o)];
    const std::string at = where + ": outputs[" + std::to_string(o) + "]";
    if (!out.contains("elements") || !out["elements"].is_array() ||
        out["elements"].size() != static_cast<std::size_t>(m.inputs)) {
      throw std::invalid_argument(at + ".elements: expected " + std::to_string(m.inputs) +
                                  " elements");
    }
    for (int i = 0; i < m.inputs; ++i) {
      const nlohmann::json& e = out["elements"][static_cast<std::size_t>(i)];
      const std::string el = at + ".elements[" + std::to_string(i) + "]";
      ElementEstimate& est = m.element(o, i);
      est.value = {number(e, "K", el), number(e, "Td", el), number(e, "Tp1", el),
                   number(e, "Tp2", el)};
      const bool finite = std::isfinite(est.value.gain) && std::isfinite(est.value.delay_min) &&
                          std::isfinite(est.value.tau1_min) && std::isfinite(est.value.tau2_min);
      if (finite &&
          (est.value.delay_min < 0.0 || est.value.tau1_min < 0.0 || est.value.tau2_min < 0.0)) {
        throw std::invalid_argument(el + ": Td, Tp1, Tp2: expected >= 0");
      }
      est.status = finite ? ElementStatus::identified : ElementStatus::input_not_moved;
      const std::string status = text(e, "status", el);
      const std::string reason = text(e, "reason", el);
      if (finite && status == "weak_gain") est.status = ElementStatus::weak_gain;
      if (!finite) est.reason = reason.empty() ? "not estimated" : reason;
    }
  }
  return named;
}

namespace {
std::string listed(const std::vector<std::string>& names) {
  std::string s = "[";
  for (const std::string& n : names) s += (s.size() > 1 ? ", " : "") + n;
  return s + "]";
}
}  // namespace

void check_same_channels(const ModelChannels& model, const std::string& model_path,
                         const std::vector<std::string>& run_inputs,
                         const std::vector<std::string>& run_outputs, const std::string& run_path) {
  for (const auto& [kind, ours, theirs] : {std::tuple{"inputs", &model.inputs, &run_inputs},
                                           std::tuple{"outputs", &model.outputs, &run_outputs}}) {
    if (*ours != *theirs) {
      throw std::invalid_argument(model_path + ": " + kind + " = " + listed(*ours) + ", " +
                                  run_path + ": " + kind + " = " + listed(*theirs) +
                                  "; expected the same channels in the same order");
    }
  }
}

}  // namespace excite::host::cli
