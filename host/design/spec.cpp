// SPDX-License-Identifier: MIT
#include "host/design/spec.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "base/config/document.hpp"
#include "base/config/table.hpp"
#include "host/design/case_studies.hpp"
#include "host/measures/gain_directions.hpp"

namespace excite::host {
namespace {

using ConfigTable = config::Table;  // host::Table is the design table

// prior.gain: one row per output, one number per input.
Eigen::MatrixXd read_gain(const ConfigTable& prior, int inputs) {
  const toml::node& node = *prior.get("gain");
  const toml::array* rows = node.as_array();
  if (rows == nullptr || rows->empty()) {
    prior.fail("gain", config::describe(node), "an array of rows (outputs x inputs)");
  }
  Eigen::MatrixXd g(static_cast<Eigen::Index>(rows->size()), inputs);
  for (std::size_t r = 0; r < rows->size(); ++r) {
    const std::string row_field = "gain[" + std::to_string(r) + "]";
    const toml::array* row = (*rows)[r].as_array();
    if (row == nullptr || row->size() != static_cast<std::size_t>(inputs)) {
      throw config::Error(
          prior.source(), config::position_of((*rows)[r]), prior.field(row_field),
          row ? std::to_string(row->size()) + " entries" : config::describe((*rows)[r]),
          std::to_string(inputs) + " numbers (one per input)");
    }
    for (std::size_t c = 0; c < row->size(); ++c) {
      const toml::node& cell = (*row)[c];
      const auto v = cell.value<double>();
      if (!cell.is_number() || !v || !std::isfinite(*v)) {
        throw config::Error(prior.source(), config::position_of(cell),
                            prior.field(row_field + "[" + std::to_string(c) + "]"),
                            config::describe(cell), "a finite number");
      }
      g(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = *v;
    }
  }
  return g;
}

InputSpec read_input(const ConfigTable& in) {
  in.only_keys({"name", "amplitude", "min", "max"});
  InputSpec spec_in;
  spec_in.name = in.required_text("name");
  spec_in.min = in.required_number("min");
  spec_in.max = in.required_number("max");
  // Used by input-amplitude sizing; by default the room to the nearer limit.
  spec_in.amplitude = in.number("amplitude").value_or(std::min(-spec_in.min, spec_in.max));
  return spec_in;
}

PlainMultisine read_multisine(const ConfigTable& ms) {
  ms.only_keys({"period", "first_line", "last_line", "phases", "seed", "periods"});
  constexpr std::int64_t kMax = 4294967295;  // the plan stores them as uint32
  const auto whole = [&ms](const char* key) {
    return static_cast<std::uint32_t>(ms.required_integer(key, 0, kMax, "a whole number >= 0"));
  };
  PlainMultisine m;
  m.period = whole("period");
  m.first_line = whole("first_line");
  m.last_line = whole("last_line");
  m.periods =
      static_cast<std::uint32_t>(ms.integer("periods", 0, kMax, "a whole number >= 0").value_or(1));
  m.seed =
      static_cast<std::uint32_t>(ms.integer("seed", 0, kMax, "a whole number >= 0").value_or(1));
  if (auto phases = ms.text("phases"); phases && !phases->empty()) m.phases = *phases;
  return m;
}

}  // namespace

DesignSpec parse_design_spec(std::string_view toml_text, std::string_view source_name) {
  const toml::table doc = config::parse(toml_text, source_name);
  const ConfigTable root(doc, "", source_name);
  root.only_keys({"design", "plant", "prior", "input", "multisine"});
  DesignSpec spec;
  spec.design = root.required_text("design", "a preset acronym or \"multisine\"");
  if (spec.design.empty()) {
    root.fail("design", "\"\"", "a preset acronym of Table 6.1 or \"multisine\"");
  }
  const bool plain = spec.design == "multisine";  // needs no dynamics, only its lines
  const std::string plant = root.text("plant").value_or("");

  const ConfigTable prior =
      root.required_table("prior", "a table [prior], the plant's prior knowledge");
  prior.only_keys({"inputs", "sample_time_min", "tau_low_min", "tau_high_min", "alpha", "beta",
                   "step_length_min", "gain", "sizing"});
  PriorKnowledge& p = spec.prior;
  p.plant = plant.empty() ? std::string(source_name) : plant;
  const auto number = [&prior](const char* key, bool required, double fallback) {
    return required ? prior.required_number(key) : prior.number(key).value_or(fallback);
  };
  const std::int64_t inputs = prior.required_integer("inputs", 0, 1 << 20, "an input count");
  p.sample_time_min = number("sample_time_min", true, 0.0);
  p.tau_low_min = number("tau_low_min", !plain, 0.0);
  p.tau_high_min = number("tau_high_min", !plain, 0.0);
  p.alpha = number("alpha", !plain, 2.0);
  p.beta = number("beta", !plain, 3.0);
  p.step_length_min = number("step_length_min", false, 0.0);
  if (prior.choice("sizing", {"static_output", "input_amplitude"}) == "input_amplitude") {
    p.sizing = Sizing::input_amplitude;
  }

  const std::vector<ConfigTable> input_tables = root.tables("input");
  if (inputs != static_cast<std::int64_t>(input_tables.size())) {
    prior.fail("inputs", std::to_string(inputs),
               "the number of [[input]] tables (" + std::to_string(input_tables.size()) + ")");
  }
  for (const ConfigTable& in : input_tables) p.inputs.push_back(read_input(in));
  const int declared = static_cast<int>(input_tables.size());

  if (prior.has("gain")) {
    p.gain = read_gain(prior, declared);
  } else if (!plant.empty()) {
    try {
      p.gain = case_study(plant).gain;          // the library plant's G(0)
    } catch (const std::invalid_argument& e) {  // an unknown plant: named with file and line
      root.fail("plant", "\"" + plant + "\"", std::string("a library plant (") + e.what() + ")");
    }
    if (p.gain.cols() != declared) {
      root.fail("plant", "\"" + plant + "\" (" + std::to_string(p.gain.cols()) + " inputs)",
                "a plant with the spec's " + std::to_string(declared) + " inputs");
    }
  }

  const std::optional<ConfigTable> ms = root.table("multisine");
  if (plain && !ms) {
    root.fail_missing("multisine",
                      "a [multisine] table (period, first_line, last_line) with "
                      "design = \"multisine\"");
  }
  if (!plain && ms) {
    root.fail("multisine", "(a table)", "no [multisine] table unless design = \"multisine\"");
  }
  if (plain) spec.multisine = read_multisine(*ms);

  try {
    if (plain) {
      validate_inputs(p);
    } else {
      validate(p);
    }
    if (p.gain.size() != 0)
      require_full_rank(analyse_gain(p.gain));  // refuses a singular gain by name
  } catch (const std::invalid_argument& e) {
    throw config::Error::text(source_name, {}, e.what());
  }
  return spec;
}

DesignSpec load_design_spec(const std::filesystem::path& path) {
  return parse_design_spec(config::read_file(path), path.string());
}

}  // namespace excite::host
