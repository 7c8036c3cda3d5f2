// SPDX-License-Identifier: MIT
#include "host/design/spec.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "host/design/case_studies.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {
namespace {

class SpecReader {
 public:
  explicit SpecReader(std::string_view source) : source_(source) {}

  [[noreturn]] void fail(const toml::node* where, const std::string& what) const {
    std::ostringstream msg;
    msg << source_;
    if (where != nullptr && where->source().begin) {
      msg << ":" << where->source().begin.line << ":" << where->source().begin.column;
    }
    msg << ": " << what;
    throw std::invalid_argument(msg.str());
  }

  void only_keys(const toml::table& table, const std::string& prefix,
                 const std::set<std::string>& allowed) const {
    for (const auto& [key, node] : table) {
      if (allowed.count(std::string(key.str())) == 0) {
        std::string list;
        for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
        fail(&node,
             "unknown key '" + prefix + std::string(key.str()) + "', expected one of: " + list);
      }
    }
  }

  double number(const toml::table& table, const std::string& prefix, const char* key, bool required,
                double fallback) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
      if (required) fail(&table, "missing '" + prefix + key + "', expected a number");
      return fallback;
    }
    if (const auto v = node->value<double>()) return *v;
    fail(node, "'" + prefix + key + "' is a " + type_name(*node) + ", expected a number");
  }

  std::string text(const toml::table& table, const std::string& prefix, const char* key,
                   bool required) const {
    const toml::node* node = table.get(key);
    if (node == nullptr) {
      if (required) fail(&table, "missing '" + prefix + key + "', expected a string");
      return {};
    }
    if (const auto v = node->value<std::string>()) return *v;
    fail(node, "'" + prefix + key + "' is a " + type_name(*node) + ", expected a string");
  }

  static std::string type_name(const toml::node& node) {
    std::ostringstream s;
    s << node.type();
    return s.str();
  }

 private:
  std::string source_;
};

Eigen::MatrixXd read_gain(const SpecReader& reader, const toml::node& node, int inputs) {
  const toml::array* rows = node.as_array();
  if (rows == nullptr || rows->empty())
    reader.fail(&node, "'prior.gain' must be an array of rows (outputs x inputs)");
  Eigen::MatrixXd g(static_cast<Eigen::Index>(rows->size()), inputs);
  for (std::size_t r = 0; r < rows->size(); ++r) {
    const toml::array* row = (*rows)[r].as_array();
    if (row == nullptr || row->size() != static_cast<std::size_t>(inputs)) {
      reader.fail(&(*rows)[r], "'prior.gain' row " + std::to_string(r) + " has " +
                                   std::to_string(row ? row->size() : 0) + " entries, expected " +
                                   std::to_string(inputs) + " (one per input)");
    }
    for (std::size_t c = 0; c < row->size(); ++c) {
      const auto v = (*row)[c].value<double>();
      if (!v)
        reader.fail(&(*row)[c], "'prior.gain[" + std::to_string(r) + "][" + std::to_string(c) +
                                    "]' is not a number");
      g(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = *v;
    }
  }
  return g;
}

}  // namespace

DesignSpec parse_design_spec(std::string_view toml_text, std::string_view source_name) {
  const SpecReader reader(source_name);
  toml::table root;
  try {
    root = toml::parse(toml_text, source_name);
  } catch (const toml::parse_error& e) {
    std::ostringstream msg;
    msg << source_name << ":" << e.source().begin.line << ":" << e.source().begin.column << ": "
        << e.description();
    throw std::invalid_argument(msg.str());
  }

  reader.only_keys(root, "", {"design", "plant", "prior", "input", "multisine"});
  DesignSpec spec;
  spec.design = reader.text(root, "", "design", true);
  if (spec.design.empty()) {
    reader.fail(root.get("design"),
                "design = \"\": expected a preset acronym of Table 6.1 or "
                "\"multisine\"");
  }
  const bool plain = spec.design == "multisine";  // needs no dynamics, only its lines
  const std::string plant = reader.text(root, "", "plant", false);

  const toml::table* prior = root.get_as<toml::table>("prior");
  if (prior == nullptr)
    reader.fail(&root, "missing table [prior], expected the plant's prior knowledge");
  reader.only_keys(*prior, "prior.",
                   {"inputs", "sample_time_min", "tau_low_min", "tau_high_min", "alpha", "beta",
                    "step_length_min", "gain", "sizing"});
  PriorKnowledge& p = spec.prior;
  p.plant = plant.empty() ? std::string(source_name) : plant;
  const double inputs = reader.number(*prior, "prior.", "inputs", true, 0.0);
  p.sample_time_min = reader.number(*prior, "prior.", "sample_time_min", true, 0.0);
  p.tau_low_min = reader.number(*prior, "prior.", "tau_low_min", !plain, 0.0);
  p.tau_high_min = reader.number(*prior, "prior.", "tau_high_min", !plain, 0.0);
  p.alpha = reader.number(*prior, "prior.", "alpha", !plain, 2.0);
  p.beta = reader.number(*prior, "prior.", "beta", !plain, 3.0);
  p.step_length_min = reader.number(*prior, "prior.", "step_length_min", false, 0.0);
  const std::string sizing = reader.text(*prior, "prior.", "sizing", false);
  if (sizing == "input_amplitude") {
    p.sizing = Sizing::input_amplitude;
  } else if (!sizing.empty() && sizing != "static_output") {
    reader.fail(prior->get("sizing"),
                "prior.sizing = \"" + sizing + "\", expected static_output or input_amplitude");
  }

  const toml::array* input_tables = root.get_as<toml::array>("input");
  const std::size_t declared = input_tables ? input_tables->size() : 0;
  if (inputs != static_cast<double>(declared)) {
    reader.fail(prior->get("inputs"), "prior.inputs = " + std::to_string(inputs) + ", but " +
                                          std::to_string(declared) +
                                          " [[input]] tables are given; expected equal");
  }
  for (std::size_t j = 0; j < declared; ++j) {
    const toml::table* in = (*input_tables)[j].as_table();
    const std::string prefix = "input[" + std::to_string(j) + "].";
    if (in == nullptr) reader.fail(&(*input_tables)[j], "'" + prefix + "' must be a table");
    reader.only_keys(*in, prefix, {"name", "amplitude", "min", "max"});
    InputSpec spec_in;
    spec_in.name = reader.text(*in, prefix, "name", true);
    spec_in.min = reader.number(*in, prefix, "min", true, 0.0);
    spec_in.max = reader.number(*in, prefix, "max", true, 0.0);
    // Used by input-amplitude sizing; by default the room to the nearer limit.
    spec_in.amplitude =
        reader.number(*in, prefix, "amplitude", false, std::min(-spec_in.min, spec_in.max));
    p.inputs.push_back(spec_in);
  }

  if (const toml::node* gain = prior->get("gain")) {
    p.gain = read_gain(reader, *gain, static_cast<int>(declared));
  } else if (!plant.empty()) {
    try {
      p.gain = case_study(plant).gain;          // the library plant's G(0)
    } catch (const std::invalid_argument& e) {  // an unknown plant: named with file and line
      reader.fail(root.get("plant"), e.what());
    }
    if (p.gain.cols() != static_cast<Eigen::Index>(declared)) {
      reader.fail(&root, "plant = \"" + plant + "\" has " + std::to_string(p.gain.cols()) +
                             " inputs, the spec " + std::to_string(declared));
    }
  }

  const toml::table* ms = root.get_as<toml::table>("multisine");
  if (plain != (ms != nullptr)) {
    reader.fail(
        ms, plain
                ? "design = \"multisine\" needs a [multisine] table (period, first_line, last_line)"
                : "a [multisine] table belongs to design = \"multisine\" only");
  }
  if (plain) {
    reader.only_keys(*ms, "multisine.",
                     {"period", "first_line", "last_line", "phases", "seed", "periods"});
    PlainMultisine m;
    const auto whole = [&](const char* key, bool required, double fallback) {
      const double v = reader.number(*ms, "multisine.", key, required, fallback);
      if (!(v >= 0.0 && v <= 4294967295.0 && v == std::floor(v))) {
        reader.fail(ms->get(key), "multisine." + std::string(key) + " = " + std::to_string(v) +
                                      ", expected a whole number >= 0");
      }
      return static_cast<std::uint32_t>(v);
    };
    m.period = whole("period", true, 0);
    m.first_line = whole("first_line", true, 1);
    m.last_line = whole("last_line", true, 1);
    m.periods = whole("periods", false, 1);
    m.seed = whole("seed", false, 1);
    const std::string phases = reader.text(*ms, "multisine.", "phases", false);
    if (!phases.empty()) m.phases = phases;
    spec.multisine = m;
  }

  try {
    if (plain) {
      validate_inputs(p);
    } else {
      validate(p);
    }
    if (p.gain.size() != 0)
      require_full_rank(analyse_gain(p.gain));  // refuses a singular gain by name
  } catch (const std::invalid_argument& e) {
    reader.fail(nullptr, e.what());
  }
  return spec;
}

DesignSpec load_design_spec(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_design_spec(text.str(), path.string());
}

}  // namespace excite::host
