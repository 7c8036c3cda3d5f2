// SPDX-License-Identifier: MIT
#include "host/export/formats.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "host/export/code_text.hpp"
#include "host/export/step_response.hpp"

namespace excite::host {
namespace {

constexpr const char* kTransferFormat = "excite transfer matrix v1";

// Shortest text that reads back as the same double.
std::string exact(double v) {
  char buffer[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    if (std::strtod(buffer, nullptr) == v) break;
  }
  return buffer;
}

// The element's rational part in descending powers of s, without leading zeros: the
// numerator with the gain, and the denominator (element.hpp; vanishing time constants
// dropped at the model's sample time).
std::vector<double> descending(sim::Polynomial ascending) {
  while (ascending.size() > 1 && ascending.back() == 0.0) ascending.pop_back();
  return {ascending.rbegin(), ascending.rend()};
}
std::vector<double> numerator(const ElementModel& p, double T) {
  return descending(to_term(p, T).numerator());
}
std::vector<double> denominator(const ElementModel& p, double T) {
  return descending(to_term(p, T).denominator());
}

// The structures' formula, as the exports' comments state it.
constexpr const char* kElementFormula =
    "K (Tz s + 1) e^(-Td s) / ((Tp1 s + 1)(Tp2 s + 1)), or with (Tn^2 s^2 + 2 zeta Tn s + 1) "
    "for (Tp2 s + 1) (underdamped), or s for (Tp2 s + 1) (integrator); see 'structure'";

std::string list(const std::vector<double>& v, const char* separator) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? separator : "") + exact(v[i]);
  return out;
}

// Every name and the source as text the exports can carry: valid UTF-8 (Python source and
// JSON are), each refused naming its field otherwise.
void require_utf8_names(const NamedModel& m) {
  require_utf8("source (the model file's name)", m.source);
  for (const auto& [key, names] :
       {std::pair{"inputs", &m.inputs}, std::pair{"outputs", &m.outputs}}) {
    for (std::size_t k = 0; k < names->size(); ++k) {
      require_utf8(comment_text(m.source) + ": " + key + "[" + std::to_string(k) + "]",
                   (*names)[k]);
    }
  }
}

// {'a', 'it''s'}: each name a MATLAB char literal, refused naming its field when it cannot
// be one (code_text.hpp).
std::string matlab_cell(const NamedModel& m, const char* key,
                        const std::vector<std::string>& names) {
  std::string out = "{";
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += (i ? ", " : "") +
           matlab_string_literal(
               comment_text(m.source) + ": " + key + "[" + std::to_string(i) + "]", names[i]);
  }
  return out + "}";
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string out = "\"";
  for (const char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

double input_delay(const NamedModel& m, int in) {
  double d = std::numeric_limits<double>::infinity();
  for (int o = 0; o < m.model.outputs; ++o) d = std::min(d, m.model.element(o, in).value.delay_min);
  return d;
}

// A number, or null for NaN and ±inf (JSON has neither).
nlohmann::json json_number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json transfer(const NamedModel& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int o = 0; o < m.model.outputs; ++o) {
    nlohmann::json row = nlohmann::json::array();
    for (int i = 0; i < m.model.inputs; ++i) {
      const ElementEstimate& e = m.model.element(o, i);
      const double T = m.model.sample_time_min;
      nlohmann::json element = {{"structure", to_string(e.value.structure)}};
      for (const int k : free_parameters(e.value.structure))
        element[parameter_name(static_cast<Parameter>(k))] = e.value[k];
      element["num"] = numerator(e.value, T);
      element["den"] = denominator(e.value, T);
      element["status"] = to_string(e.status);
      element["grade"] = to_string(e.grade);
      nlohmann::json se = nlohmann::json::object();
      nlohmann::json cov = nlohmann::json::array();
      const std::span<const int> free = free_parameters(e.value.structure);
      for (const int a : free) {
        se[parameter_name(static_cast<Parameter>(a))] = json_number(e.std_error[a]);
        nlohmann::json cov_row = nlohmann::json::array();
        for (const int b : free) cov_row.push_back(json_number(e.covariance(a, b)));
        cov.push_back(cov_row);
      }
      element["se"] = se;
      element["covariance"] = cov;  // over the parameters in the order listed, null unknown
      row.push_back(element);
    }
    rows.push_back(row);
  }
  return {{"format", kTransferFormat},
          {"source", m.source},
          {"time_unit", "min"},
          {"sample_time_min", m.model.sample_time_min},
          {"inputs", m.inputs},
          {"outputs", m.outputs},
          {"element", std::string(kElementFormula) + "; num, den: descending powers of s"},
          {"elements", rows}};
}

double number_at(const nlohmann::json& j, const char* key, const std::string& where) {
  if (!j.contains(key) || !j.at(key).is_number()) {
    throw std::invalid_argument(where + "." + key + ": " +
                                (j.contains(key) ? j.at(key).dump() : std::string("missing")) +
                                ", expected a number");
  }
  return j.at(key).get<double>();
}

}  // namespace

void require_every_element(const NamedModel& m) {
  for (int o = 0; o < m.model.outputs; ++o) {
    for (int i = 0; i < m.model.inputs; ++i) {
      const ElementEstimate& e = m.model.element(o, i);
      if (e.estimated()) continue;
      throw std::invalid_argument(
          m.source + ": outputs[" + std::to_string(o) + "].elements[" + std::to_string(i) + "] (" +
          m.outputs.at(static_cast<std::size_t>(o)) + " <- " +
          m.inputs.at(static_cast<std::size_t>(i)) + "): not estimated (" + to_string(e.status) +
          (e.reason.empty() ? "" : ": " + e.reason) +
          "), expected every element to have parameters before it is exported");
    }
  }
}

std::string step_csv(const NamedModel& m, int horizon_samples, bool bands) {
  if (horizon_samples < 1) {
    throw std::invalid_argument("horizon: " + std::to_string(horizon_samples) +
                                " samples, expected at least 1");
  }
  require_every_element(m);
  require_utf8_names(m);
  const double T = m.model.sample_time_min;
  std::ostringstream out;
  out << "# excite step response v1\n# source: " << comment_text(m.source)
      << "\n# sample_time_min: " << exact(T) << "\n# horizon: " << horizon_samples << " samples ("
      << exact(horizon_samples * T) << " min)\n"
      << "# s_k = y(kT) after a unit step of the MV at t = 0, k = 1 ... horizon (CV units per "
         "MV unit); element "
      << kElementFormula << "\n";
  if (bands) {
    out << "# -2s, +2s: s_k -/+ 2 sigma of s(kT) from the element's parameter covariance "
           "(empty: not known)\n";
  }
  out << "k,t_min";
  for (int o = 0; o < m.model.outputs; ++o) {
    for (int i = 0; i < m.model.inputs; ++i) {
      const std::string name =
          m.outputs[static_cast<std::size_t>(o)] + " <- " + m.inputs[static_cast<std::size_t>(i)];
      out << ',' << csv_field(name);
      if (bands) out << ',' << csv_field(name + " -2s") << ',' << csv_field(name + " +2s");
    }
  }
  out << '\n';
  std::vector<double> times;
  for (int k = 1; k <= horizon_samples; ++k) times.push_back(k * T);
  std::vector<StepBand> band;  // per element, when asked for
  for (int o = 0; bands && o < m.model.outputs; ++o) {
    for (int i = 0; i < m.model.inputs; ++i)
      band.push_back(step_band(m.model.element(o, i), times));
  }
  for (int k = 1; k <= horizon_samples; ++k) {
    const double t = times[static_cast<std::size_t>(k - 1)];
    out << k << ',' << exact(t);
    for (int o = 0; o < m.model.outputs; ++o) {
      for (int i = 0; i < m.model.inputs; ++i) {
        out << ',' << exact(step_response(m.model.element(o, i).value, t));
        if (!bands) continue;
        const StepBand& b = band[static_cast<std::size_t>(o * m.model.inputs + i)];
        const double s = b.response[static_cast<std::size_t>(k - 1)];
        const double sigma = b.sigma[static_cast<std::size_t>(k - 1)];
        if (std::isfinite(sigma)) {
          out << ',' << exact(s - 2.0 * sigma) << ',' << exact(s + 2.0 * sigma);
        } else {
          out << ",,";
        }
      }
    }
    out << '\n';
  }
  return out.str();
}

std::string matlab_script(const NamedModel& m) {
  require_every_element(m);
  require_utf8_names(m);
  const std::string input_names = matlab_cell(m, "inputs", m.inputs);
  const std::string output_names = matlab_cell(m, "outputs", m.outputs);
  const int p = m.model.outputs, n = m.model.inputs;
  std::ostringstream s;
  s << "% excite model export (MATLAB Control System Toolbox; Octave control package)\n"
    << "% source: " << comment_text(m.source) << "\n"
    << "% G(s) per CV x MV: " << kElementFormula << ", time in minutes\n"
    << "% identified at sample time " << exact(m.model.sample_time_min) << " min\n";
  const double T = m.model.sample_time_min;
  s << "num = {";
  for (int o = 0; o < p; ++o) {
    for (int i = 0; i < n; ++i)
      s << (i ? ", " : "") << '[' << list(numerator(m.model.element(o, i).value, T), " ") << ']';
    s << (o + 1 < p ? "; " : "");
  }
  s << "};\nden = {";
  for (int o = 0; o < p; ++o) {
    for (int i = 0; i < n; ++i)
      s << (i ? ", " : "") << '[' << list(denominator(m.model.element(o, i).value, T), " ") << ']';
    s << (o + 1 < p ? "; " : "");
  }
  s << "};\ninput_delay_min = [";
  for (int i = 0; i < n; ++i) s << (i ? " " : "") << exact(input_delay(m, i));
  s << "];\nio_delay_min = [";
  for (int o = 0; o < p; ++o) {
    for (int i = 0; i < n; ++i) {
      s << (i ? " " : "") << exact(m.model.element(o, i).value.delay_min - input_delay(m, i));
    }
    s << (o + 1 < p ? "; " : "");
  }
  s << "];\ninput_names = " << input_names << ";\noutput_names = " << output_names << ";\n"
    << "if exist('OCTAVE_VERSION', 'builtin')\n"
    << "  pkg load control\n"
    << "  % The control package has no delay properties: G holds the rational part; the\n"
    << "  % delays are input_delay_min (per MV) + io_delay_min (per CV x MV).\n"
    << "  G = tf(num, den, 'inname', input_names, 'outname', output_names);\n"
    << "else\n"
    << "  G = tf(num, den, 'InputDelay', input_delay_min', 'IODelay', io_delay_min, ...\n"
    << "         'InputName', input_names, 'OutputName', output_names, 'TimeUnit', 'minutes');\n"
    << "end\n";
  return s.str();
}

std::string python_control_script(const NamedModel& m) {
  require_every_element(m);
  require_utf8_names(m);
  std::ostringstream s;
  s << "#!/usr/bin/env python3\n"
    << "\"\"\"excite model export for python-control; source: "
    << python_triple_quoted_body(m.source, '"') << ".\n\n"
    << "G(s) per CV x MV: " << kElementFormula << ", time in minutes.\n"
    << "G is the rational part (python-control's tf has no delay); DELAYS_MIN holds the\n"
    << "delays, with_pade(order) gives G with every delay by a Pade approximation.\n\"\"\"\n"
    << "import json\n\nimport control\n\n"
    // The model's JSON (pure ASCII) in a literal no name can close.
    << "MODEL = json.loads('''"
    << python_triple_quoted_body(transfer(m).dump(1, ' ', /*ensure_ascii=*/true), '\'')
    << "''')\n\n"
    << "INPUTS = MODEL['inputs']\nOUTPUTS = MODEL['outputs']\n"
    << "ELEMENTS = MODEL['elements']  # rows = CVs, columns = MVs\n"
    << "DELAYS_MIN = [[e['Td'] for e in row] for row in ELEMENTS]\n\n"
    << "G = control.tf([[e['num'] for e in row] for row in ELEMENTS],\n"
    << "               [[e['den'] for e in row] for row in ELEMENTS],\n"
    << "               inputs=INPUTS, outputs=OUTPUTS, name='excite_model')\n\n\n"
    << "def with_pade(order=3):\n"
    << "    \"\"\"G with each element's delay replaced by a Pade approximation of `order`.\"\"\"\n"
    << "    nums, dens = [], []\n"
    << "    for row in ELEMENTS:\n"
    << "        nums.append([])\n"
    << "        dens.append([])\n"
    << "        for e in row:\n"
    << "            element = control.tf(e['num'], e['den'])\n"
    << "            if e['Td'] > 0:\n"
    << "                element = element * control.tf(*control.pade(e['Td'], order))\n"
    << "            nums[-1].append(list(element.num[0][0]))\n"
    << "            dens[-1].append(list(element.den[0][0]))\n"
    << "    return control.tf(nums, dens, inputs=INPUTS, outputs=OUTPUTS)\n\n\n"
    << "if __name__ == '__main__':\n"
    << "    print(G)\n"
    << "    print('delays [min]:', DELAYS_MIN)\n";
  return s.str();
}

std::string transfer_json(const NamedModel& m) {
  require_every_element(m);
  require_utf8_names(m);
  return transfer(m).dump(2) + "\n";
}

NamedModel read_transfer_json(const std::string& text, const std::string& source) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument(source + ": not JSON (" + e.what() + ")");
  }
  if (!j.is_object() || j.value("format", "") != kTransferFormat) {
    throw std::invalid_argument(source + ": format, expected \"" + kTransferFormat + "\"");
  }
  NamedModel m;
  m.source = source;
  m.model.sample_time_min = number_at(j, "sample_time_min", source);
  m.inputs = j.at("inputs").get<std::vector<std::string>>();
  m.outputs = j.at("outputs").get<std::vector<std::string>>();
  m.model.inputs = static_cast<int>(m.inputs.size());
  m.model.outputs = static_cast<int>(m.outputs.size());
  const nlohmann::json& rows = j.at("elements");
  if (!rows.is_array() || rows.size() != m.outputs.size()) {
    throw std::invalid_argument(source + ": elements, expected " +
                                std::to_string(m.outputs.size()) + " rows");
  }
  for (int o = 0; o < m.model.outputs; ++o) {
    const nlohmann::json& row = rows[static_cast<std::size_t>(o)];
    if (!row.is_array() || row.size() != m.inputs.size()) {
      throw std::invalid_argument(source + ": elements[" + std::to_string(o) + "], expected " +
                                  std::to_string(m.inputs.size()) + " elements");
    }
    for (int i = 0; i < m.model.inputs; ++i) {
      const std::string where =
          source + ": elements[" + std::to_string(o) + "][" + std::to_string(i) + "]";
      const nlohmann::json& e = row[static_cast<std::size_t>(i)];
      ElementEstimate est;
      const std::string name = e.value("structure", "two_poles");
      const std::optional<Structure> structure = structure_from_string(name);
      if (!structure) {
        throw std::invalid_argument(where + ".structure: \"" + name.substr(0, 40) +
                                    "\", expected first_order, two_poles, two_poles_zero, "
                                    "integrator, underdamped or underdamped_lag_zero");
      }
      est.value.structure = *structure;
      for (const int k : free_parameters(*structure))
        est.value[k] = number_at(e, parameter_name(static_cast<Parameter>(k)), where);
      try {
        check_element(est.value);
      } catch (const std::invalid_argument& bad) {
        throw std::invalid_argument(where + "." + bad.what());
      }
      est.status = e.value("status", "identified") == "weak_gain" ? ElementStatus::weak_gain
                                                                  : ElementStatus::identified;
      m.model.elements.push_back(est);
    }
  }
  return m;
}

}  // namespace excite::host
