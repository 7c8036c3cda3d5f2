// SPDX-License-Identifier: MIT
#include "host/export/model_file.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "host/export/json_util.hpp"
#include "host/identify/identification_text.hpp"
#include "host/output/input_path.hpp"
#include "host/output/json_file.hpp"

namespace excite::host {
namespace {

// v2 added each element's structure, its parameters beyond (6.1.1) and its covariance; a
// v1 file (every element two_poles, no covariance) still reads.
constexpr const char* kFormat = "excite model v2";
constexpr const char* kFormatV1 = "excite model v1";

// Every parameter (those outside the structure at their neutral values, so K, Td, Tp1, Tp2
// mean what v1 said for every structure except where Tz, Tn, zeta say more).
nlohmann::json parameters(const ElementModel& p) {
  nlohmann::json j = nlohmann::json::object();
  for (int k = 0; k < kParameters; ++k)
    j[parameter_name(static_cast<Parameter>(k))] = to_json(p[k]);
  return j;
}

// The structure's parameters only (standard errors: the others have none).
nlohmann::json free_parameters_json(const ElementModel& p, Structure s) {
  nlohmann::json j = nlohmann::json::object();
  for (const int k : free_parameters(s))
    j[parameter_name(static_cast<Parameter>(k))] = to_json(p[k]);
  return j;
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

// The element's standard errors, covariance and grade when the file has them (v2; NaN and
// grade D otherwise). Only the structure's parameters.
void read_uncertainty(const nlohmann::json& e, const std::string& where, ElementEstimate& est) {
  const std::span<const int> free = free_parameters(est.value.structure);
  est.std_error = est.value;
  for (int k = 0; k < kParameters; ++k) est.std_error[k] = std::numeric_limits<double>::quiet_NaN();
  if (e.contains("se") && e["se"].is_object()) {
    for (const int k : free) {
      const char* name = parameter_name(static_cast<Parameter>(k));
      if (e["se"].contains(name)) est.std_error[k] = number(e["se"], name, where + ".se");
    }
  }
  if (e.contains("covariance") && !e["covariance"].is_null()) {
    const nlohmann::json& c = e["covariance"];
    if (!c.is_array() || c.size() != free.size()) {
      throw std::invalid_argument(field(where, "covariance") + " = " + shown(c) + ", expected " +
                                  std::to_string(free.size()) + " rows (one per parameter of " +
                                  to_string(est.value.structure) + ")");
    }
    for (std::size_t a = 0; a < free.size(); ++a) {
      const std::string row_at = where + ".covariance[" + std::to_string(a) + "]";
      if (!c[a].is_array() || c[a].size() != free.size()) {
        throw std::invalid_argument(row_at + " = " + shown(c[a]) + ", expected " +
                                    std::to_string(free.size()) + " numbers");
      }
      for (std::size_t b = 0; b < free.size(); ++b) {
        const nlohmann::json& v = c[a][b];
        if (!v.is_null() && !v.is_number()) {
          throw std::invalid_argument(row_at + "[" + std::to_string(b) + "] = " + shown(v) +
                                      ", expected a number or null");
        }
        est.covariance(free[a], free[b]) =
            v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>();
      }
    }
  }
  if (e.contains("K_projected") && !e["K_projected"].is_null()) {
    const nlohmann::json& p = e["K_projected"];
    const bool numbers = p.is_object() && p.contains("lower") && p["lower"].is_number() &&
                         p.contains("upper") && p["upper"].is_number();
    if (!numbers || !(p["lower"].get<double>() <= est.value.gain &&
                      est.value.gain <= p["upper"].get<double>())) {
      throw std::invalid_argument(field(where, "K_projected") + " = " + shown(p) +
                                  ", expected {lower, upper, why} with lower <= K <= upper");
    }
    est.projected_gain = ProjectedGain{{p["lower"].get<double>(), p["upper"].get<double>()},
                                       text(p, "why", where + ".K_projected")};
  }
  const std::string grade = text(e, "grade", where);
  for (const Grade g : {Grade::A, Grade::B, Grade::C, Grade::D}) {
    if (grade == to_string(g)) est.grade = g;
  }
  est.grade_reason = text(e, "grade_reason", where);
}

// The row's gain covariance (n × n) when the file has it (null entries NaN).
std::optional<Eigen::MatrixXd> read_gain_covariance(const nlohmann::json& out,
                                                    const std::string& where, int inputs) {
  if (!out.contains("gain_covariance") || out["gain_covariance"].is_null()) return std::nullopt;
  const nlohmann::json& c = out["gain_covariance"];
  const auto n = static_cast<std::size_t>(inputs);
  Eigen::MatrixXd cov(inputs, inputs);
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      if (!c.is_array() || c.size() != n || !c[a].is_array() || c[a].size() != n ||
          !(c[a][b].is_null() || c[a][b].is_number())) {
        throw std::invalid_argument(field(where, "gain_covariance") + " = " + shown(c) +
                                    ", expected " + std::to_string(n) + " x " + std::to_string(n) +
                                    " numbers or nulls");
      }
      cov(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) =
          c[a][b].is_null() ? std::numeric_limits<double>::quiet_NaN() : c[a][b].get<double>();
    }
  }
  return cov;
}

// G(0) of a model with its standard errors, element by element.
nlohmann::json gains_json(const IdentifiedModel& m) {
  nlohmann::json g = nlohmann::json::array(), se = nlohmann::json::array();
  for (int o = 0; o < m.outputs; ++o) {
    nlohmann::json row = nlohmann::json::array(), row_se = nlohmann::json::array();
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      row.push_back(e.estimated() ? nlohmann::json(e.value.static_gain()) : nlohmann::json());
      row_se.push_back(std::isfinite(e.std_error.gain) ? nlohmann::json(e.std_error.gain)
                                                       : nlohmann::json());
    }
    g.push_back(row);
    se.push_back(row_se);
  }
  return {{"gain", g}, {"gain_std_error", se}};
}

// Each output's number of noise-model parameters (0: white, the output-error fit; an AR's
// order; 2 for the ARMA(1,1)).
std::vector<int> noise_orders(const std::vector<ArNoiseModel>& noise) {
  std::vector<int> orders;
  for (const ArNoiseModel& a : noise) orders.push_back(a.parameters());
  return orders;
}

// Each output's noise model by name: "white", "AR(n)" or "ARMA(1,1)".
std::vector<std::string> noise_names(const std::vector<ArNoiseModel>& noise) {
  std::vector<std::string> names;
  for (const ArNoiseModel& a : noise) names.push_back(a.name());
  return names;
}

// One element of the model file (model_json).
nlohmann::json element_json(const ElementEstimate& e, const std::string& input) {
  nlohmann::json j = parameters(e.value);
  j["structure"] = to_string(e.value.structure);
  j["input"] = input;
  j["se"] = free_parameters_json(e.std_error, e.value.structure);
  nlohmann::json covariance = nlohmann::json::array();  // over "se"'s parameters, in order
  for (const int a : free_parameters(e.value.structure)) {
    nlohmann::json row = nlohmann::json::array();
    for (const int b : free_parameters(e.value.structure))
      row.push_back(to_json(e.covariance(a, b)));
    covariance.push_back(row);
  }
  j["covariance"] = covariance;
  // The reported 95 % interval of K (model.hpp, gain_interval_95), and the projection it
  // holds where the element has one (read back; the interval is derived).
  const GainBounds interval = gain_interval_95(e);
  if (std::isfinite(interval.lower) && std::isfinite(interval.upper))
    j["K_interval95"] = {interval.lower, interval.upper};
  if (const auto& p = e.projected_gain) {
    j["K_projected"] = {{"lower", p->bounds.lower}, {"upper", p->bounds.upper}, {"why", p->why}};
  }
  j["status"] = to_string(e.status);
  j["reason"] = e.reason;
  j["on_bound"] = e.on_bound();
  j["grade"] = to_string(e.grade);
  j["grade_reason"] = e.grade_reason;
  return j;
}

}  // namespace

nlohmann::json closed_loop_json(const ClosedLoopIdentification& id, const runlog::RunLog& log,
                                bool direct_written) {
  nlohmann::json bias = nlohmann::json::array();
  for (const GainDisagreement& d : id.feedback_bias) {
    bias.push_back({{"element", element_name(log, d.output, d.input)},
                    {"two_stage", d.two_stage},
                    {"direct", d.direct},
                    {"sigma", d.sigma}});
  }
  std::vector<double> fit(id.stage1.fit_percent.data(),
                          id.stage1.fit_percent.data() + id.stage1.fit_percent.size());
  const IdentifiedModel& other = direct_written ? id.two_stage.model : id.direct.model;
  return {
      {"method", direct_written ? "direct" : "two-stage"},
      {"excitation", std::string(runlog::to_text(log.closed_loop.excitation))},
      {"controller", log.closed_loop.controller},
      {"stage1",
       {{"laguerre_functions", id.stage1.lags},
        {"laguerre_pole", id.stage1.pole},
        {"u_explained_by_r_percent", fit},
        {"two_stage_se_factor", rows_to_json(id.stage1_se_factor)},
        {"iv_gain_step", rows_to_json(id.iv_gain_step)}}},
      {"noise_model_orders",
       {{"two_stage", noise_orders(id.noise_two_stage)},
        {"direct", noise_orders(id.noise_direct)}}},
      {"noise_models",
       {{"two_stage", noise_names(id.noise_two_stage)}, {"direct", noise_names(id.noise_direct)}}},
      {direct_written ? "two_stage" : "direct", gains_json(other)},
      {"feedback_bias_suspected", bias}};
}

nlohmann::json model_json(const IdentificationResult& result,
                          const std::vector<std::string>& input_names,
                          const std::vector<std::string>& output_names) {
  const IdentifiedModel& m = result.model;
  nlohmann::json outputs = nlohmann::json::array();
  for (int o = 0; o < m.outputs; ++o) {
    nlohmann::json elements = nlohmann::json::array();
    for (int i = 0; i < m.inputs; ++i) {
      elements.push_back(
          element_json(m.element(o, i), input_names.at(static_cast<std::size_t>(i))));
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
    if (!fit.inputs_together.empty()) out["inputs_together"] = fit.inputs_together;
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

namespace {

// One element of a model file (`el` names it in errors): its structure, the structure's
// parameters, and where they are finite its checks and uncertainty; else why it is unknown.
ElementEstimate read_element(const nlohmann::json& e, const std::string& el) {
  ElementEstimate est;
  const std::string structure = text(e, "structure", el);
  const std::optional<Structure> s =
      structure.empty() ? Structure::two_poles : structure_from_string(structure);
  if (!s) {
    throw std::invalid_argument(field(el, "structure") + " = " + shown(e["structure"]) +
                                ", expected first_order, two_poles, two_poles_zero, "
                                "integrator, underdamped or underdamped_lag_zero");
  }
  est.value = with_structure(ElementModel{}, *s);
  bool finite = true;
  for (const int k : free_parameters(*s)) {
    est.value[k] = number(e, parameter_name(static_cast<Parameter>(k)), el);
    finite &= std::isfinite(est.value[k]);
  }
  if (finite) {
    try {
      check_element(est.value);
    } catch (const std::invalid_argument& bad) {
      throw std::invalid_argument(el + "." + bad.what());
    }
    read_uncertainty(e, el, est);
  }
  est.status = finite ? ElementStatus::identified : ElementStatus::input_not_moved;
  const std::string status = text(e, "status", el);
  const std::string reason = text(e, "reason", el);
  if (finite && status == "weak_gain") est.status = ElementStatus::weak_gain;
  if (!finite) est.reason = reason.empty() ? "not estimated" : reason;
  return est;
}

// The model's channel names, their counts checked (1 to kMaxModelChannels) before any
// allocation: a 256 KB file once asked for 36 M elements (8.8 GB).
void read_channels(const nlohmann::json& j, const std::string& where, NamedModel& named) {
  for (const char* key : {"inputs", "outputs"}) {
    if (!j.contains(key) || !j[key].is_array()) {
      throw std::invalid_argument(where + ": " + key + " = " +
                                  (j.contains(key) ? shown(j[key]) : "(missing)") +
                                  ", expected an array");
    }
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
                                    "], expected a channel name");
      }
      names->push_back(name->get<std::string>());
    }
  }
}

}  // namespace

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
  if (!j.is_object() || !j.contains("format") ||
      (j["format"] != kFormat && j["format"] != kFormatV1)) {
    throw std::invalid_argument(where + ": format, expected \"" + kFormat + "\" or \"" + kFormatV1 +
                                "\" (a file from excite identify -o)");
  }
  NamedModel named;
  named.source = where;
  IdentifiedModel& m = named.model;
  m.sample_time_min = number(j, "sample_time_min", where + ":");
  if (!(m.sample_time_min > 0.0))
    throw std::invalid_argument(where + ": sample_time_min = " + std::to_string(m.sample_time_min) +
                                ", expected > 0");
  read_channels(j, where, named);
  m.inputs = static_cast<int>(j["inputs"].size());
  m.outputs = static_cast<int>(j["outputs"].size());
  m.elements.resize(static_cast<std::size_t>(m.inputs * m.outputs));
  std::vector<Eigen::MatrixXd> covariances;  // per output, when the file has every one
  bool every_covariance = true;
  for (int o = 0; o < m.outputs; ++o) {
    const nlohmann::json& out = j["outputs"][static_cast<std::size_t>(o)];
    const std::string at = where + ": outputs[" + std::to_string(o) + "]";
    if (!out.contains("elements") || !out["elements"].is_array() ||
        out["elements"].size() != static_cast<std::size_t>(m.inputs)) {
      throw std::invalid_argument(at + ".elements, expected " + std::to_string(m.inputs) +
                                  " elements");
    }
    for (int i = 0; i < m.inputs; ++i) {
      const nlohmann::json& e = out["elements"][static_cast<std::size_t>(i)];
      const std::string el = at + ".elements[" + std::to_string(i) + "]";
      m.element(o, i) = read_element(e, el);
    }
    if (const auto cov = read_gain_covariance(out, at, m.inputs)) {
      covariances.push_back(*cov);
    } else {
      every_covariance = false;
    }
  }
  if (every_covariance) m.gain_covariance = std::move(covariances);
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
                                  ", expected the same channels in the same order");
    }
  }
}

}  // namespace excite::host
