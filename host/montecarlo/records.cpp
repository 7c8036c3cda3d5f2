// SPDX-License-Identifier: MIT
#include "host/montecarlo/records.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"
#include "host/output/input_file.hpp"

namespace excite::host::montecarlo {
namespace {

using nlohmann::json;

// A run.json or a unit file is about 1 KB (a 100-point length grid on a 4×4 plant: 6 KB).
constexpr std::uintmax_t kMaxRecordBytes = 1 << 20;

// A regular file of bounded size (a FIFO is refused, not waited on; /dev/zero is refused,
// not read into memory), parsed as JSON.
json parse(const std::filesystem::path& file, const char* what) {
  std::string text;
  try {
    text = read_input_file(file, kMaxRecordBytes, what);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(e.what());
  }
  const json j = json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded())
    throw std::runtime_error(file.string() + ": text = not JSON, expected " + what);
  return j;
}

// Reads field `key` of `object`, naming the file and the field when it is missing or of the
// wrong type.
class Reader {
 public:
  Reader(const std::filesystem::path& file, const json& object) : file_(file), object_(object) {
    if (!object_.is_object())
      throw std::runtime_error(file_.string() + ": top level = " +
                               std::string(object_.type_name()) + ", expected a JSON object");
  }
  const json& at(const char* key) const {
    if (!object_.contains(key))
      throw std::runtime_error(file_.string() + ": " + key + " = (missing), expected a value");
    return object_.at(key);
  }
  [[noreturn]] void wrong(const char* key, const char* expected) const {
    std::string value = at(key).dump();  // JSON: control characters escaped
    if (value.size() > 60) value = value.substr(0, 60) + "…";
    throw std::runtime_error(file_.string() + ": " + key + " = " + value + ", expected " +
                             expected);
  }
  double real(const char* key) const {
    const json& v = at(key);
    if (v.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!v.is_number()) wrong(key, "a number or null");
    return v.get<double>();
  }
  long long integer(const char* key) const {
    const json& v = at(key);
    if (!v.is_number_integer()) wrong(key, "an integer");
    if (v.is_number_unsigned() && v.get<std::uint64_t>() > std::uint64_t{INT64_MAX})
      wrong(key, "an integer below 2^63");
    return v.get<long long>();
  }
  // An integer in [low, high], checked before any use (a seeds of 2e9 once asked for 1.5 GB).
  long long integer_in(const char* key, long long low, long long high) const {
    const long long v = integer(key);
    if (v < low || v > high) {
      wrong(key,
            ("an integer from " + std::to_string(low) + " to " + std::to_string(high)).c_str());
    }
    return v;
  }
  std::uint64_t unsigned_integer(const char* key) const {
    const json& v = at(key);
    if (!v.is_number_unsigned()) wrong(key, "an integer >= 0");
    return v.get<std::uint64_t>();
  }
  bool boolean(const char* key) const {
    const json& v = at(key);
    if (!v.is_boolean()) wrong(key, "true or false");
    return v.get<bool>();
  }
  std::string string(const char* key) const {
    const json& v = at(key);
    if (!v.is_string()) wrong(key, "a string");
    return v.get<std::string>();
  }
  std::vector<double> reals(const char* key) const {
    const json& v = at(key);
    if (!v.is_array()) wrong(key, "an array of numbers");
    std::vector<double> out;
    for (const json& x : v) {
      if (!x.is_number()) wrong(key, "an array of numbers");
      out.push_back(x.get<double>());
    }
    return out;
  }

 private:
  const std::filesystem::path& file_;
  const json& object_;
};

json accuracy_json(const Accuracy& a) {
  return {{"gain_identified", a.gain_identified},
          {"sigma_n_error", json_number(a.sigma_n_error)},
          {"weakest_angle_deg", json_number(a.weakest_angle_deg)},
          {"minor_signs_right", a.minor_signs_right},
          {"met", a.met}};
}

}  // namespace

json json_number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

double number_of(const json& v) {
  return v.is_number() ? v.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

json config_json(const Config& c) {
  json j = {{"format", "excite montecarlo run v1"},
            {"plant", c.plant},
            {"designs", c.designs},
            {"seeds", c.seeds},
            {"first_seed", c.first_seed},
            {"noise_variance", c.noise_variance},
            {"length_step_percent", c.length_step_percent},
            {"perturb_percent", c.perturb_percent},
            {"length_grid_start", c.length_grid_start == GridStart::warm ? "warm" : "cold"},
            {"shard", std::to_string(c.shard.index) + "/" + std::to_string(c.shard.count)}};
  if (c.closed_loop.on()) {
    const ClosedLoopConfig& l = c.closed_loop;
    j["closed_loop"] = {{"controller", l.controller},
                        {"excitation", l.excitation},
                        {"method", l.method},
                        {"limit_fraction", l.limit_fraction},
                        {"mv_fraction", l.mv_fraction},
                        {"directions", l.directions},
                        {"switching", l.switching},
                        {"prbs_phase", l.prbs_phase},
                        {"controller_perturb_percent", l.model_perturb_percent},
                        {"disturbance_std", l.disturbance_std},
                        {"disturbance_tau_min", l.disturbance_tau_min}};
  }
  return j;
}

Config read_config(const std::filesystem::path& file) {
  const json j = parse(file, "a Monte Carlo run's run.json");
  const Reader r(file, j);
  if (r.string("format") != "excite montecarlo run v1")
    r.wrong("format", "\"excite montecarlo run v1\"");
  Config c;
  c.plant = r.string("plant");
  std::string acronyms;
  for (const PresetInfo& p : presets())
    acronyms += (acronyms.empty() ? "" : ", ") + std::string(p.acronym);
  const std::string design_names = "an array of design names from: " + acronyms;
  if (!r.at("designs").is_array() || r.at("designs").size() > presets().size())
    r.wrong("designs", design_names.c_str());
  for (const json& d : r.at("designs")) {
    const auto known = [&](const PresetInfo& p) {
      return d.is_string() && p.acronym == d.get<std::string>();
    };
    if (std::none_of(presets().begin(), presets().end(), known))
      r.wrong("designs", design_names.c_str());
    c.designs.push_back(d.get<std::string>());
  }
  c.seeds = static_cast<int>(r.integer_in("seeds", 1, 1000000));
  c.first_seed = r.unsigned_integer("first_seed");
  c.noise_variance = r.real("noise_variance");
  c.length_step_percent = static_cast<int>(r.integer_in("length_step_percent", 0, 100));
  // Absent in the folders of runs before --perturb: the nominal plant.
  if (j.contains("perturb_percent")) c.perturb_percent = r.real("perturb_percent");
  // Absent in the folders of runs before the warm grid: every prefix identified cold.
  c.length_grid_start = GridStart::cold;
  if (j.contains("length_grid_start")) {
    const std::string start = r.string("length_grid_start");
    if (start != "warm" && start != "cold") r.wrong("length_grid_start", "\"warm\" or \"cold\"");
    c.length_grid_start = start == "warm" ? GridStart::warm : GridStart::cold;
  }
  // Absent: open loop (every run before issue 41 §4).
  if (j.contains("closed_loop")) {
    const Reader l(file, r.at("closed_loop"));
    ClosedLoopConfig& cl = c.closed_loop;
    cl.controller = l.string("controller");
    if (cl.controller.empty()) l.wrong("controller", "the controller file's path");
    cl.excitation = l.string("excitation");
    cl.method = l.string("method");
    cl.limit_fraction = l.real("limit_fraction");
    cl.mv_fraction = l.real("mv_fraction");
    // Absent in the folders of runs before --directions: each CV its own signal.
    if (r.at("closed_loop").contains("directions")) cl.directions = l.string("directions");
    // Absent in the folders of runs before --switching: the designs at the plant's pace.
    cl.switching = r.at("closed_loop").contains("switching") ? l.string("switching") : "plant";
    // Absent in the folders of runs before --prbs-phase: the PRBS from its first bit.
    if (r.at("closed_loop").contains("prbs_phase"))
      cl.prbs_phase = static_cast<std::uint32_t>(l.integer_in("prbs_phase", 0, kMaxPrbsPhase));
    cl.model_perturb_percent = l.real("controller_perturb_percent");
    cl.disturbance_std = l.real("disturbance_std");
    cl.disturbance_tau_min = l.real("disturbance_tau_min");
  }
  try {
    c.shard = parse_shard(r.string("shard"));
  } catch (const std::invalid_argument&) {
    r.wrong("shard", "i/N with 1 <= i <= N <= 100000");
  }
  // The checks `excite montecarlo` makes of its options, so that a folder holds only what a
  // run could have written: the plant has a case study, the designs in Table order, each
  // once, the first seed, the noise and the perturbation in range.
  try {
    (void)case_study(c.plant);
    Config normalised = c;
    normalise(normalised);
    if (normalised.designs != c.designs)
      r.wrong("designs", "Table 6.1 acronyms in Table order, each once");
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  return c;
}

json unit_json(const UnitResult& u) {
  json lengths = json::array();
  for (const LengthPoint& p : u.lengths)
    lengths.push_back({{"percent", p.percent}, {"samples", p.samples}, {"met", p.met}});
  json sv = json::array();
  for (const double v : u.singular_values) sv.push_back(json_number(v));
  json gain = json::array();
  for (const double v : u.gain) gain.push_back(json_number(v));
  json true_gain = json::array();
  for (const double v : u.true_gain) true_gain.push_back(json_number(v));
  json j = {{"design", u.design},
            {"number", u.number},
            {"seed", u.seed},
            {"samples", u.samples},
            {"sample_time_min", u.sample_time_min},
            {"fit_avg", json_number(u.fit_avg)},
            {"crossfit_avg", json_number(u.crossfit_avg)},
            {"crossfit_worst", json_number(u.crossfit_worst)},
            {"ratio", json_number(u.ratio)},
            {"upsilon", json_number(u.upsilon)},
            {"ratio_noisy", json_number(u.ratio_noisy)},
            {"upsilon_noisy", json_number(u.upsilon_noisy)},
            {"singular_values", sv},
            {"gain", gain},
            {"true_gain", true_gain},
            {"accuracy", accuracy_json(u.accuracy)},
            {"lengths", lengths}};
  if (!u.not_run.empty()) j["not_run"] = u.not_run;
  if (std::isfinite(u.cv_peak_ratio)) {
    j["cv_peak_ratio"] = u.cv_peak_ratio;
    j["cv_violation_rows"] = u.cv_violation_rows;
  }
  return j;
}

UnitResult read_unit(const std::filesystem::path& file) {
  const json j = parse(file, "a Monte Carlo unit file");
  const Reader r(file, j);
  UnitResult u;
  u.design = r.string("design");
  u.number = static_cast<int>(r.integer("number"));
  u.seed = r.unsigned_integer("seed");
  u.samples = r.integer("samples");
  u.sample_time_min = r.real("sample_time_min");
  u.fit_avg = r.real("fit_avg");
  u.crossfit_avg = r.real("crossfit_avg");
  u.crossfit_worst = r.real("crossfit_worst");
  u.ratio = r.real("ratio");
  u.upsilon = r.real("upsilon");
  u.ratio_noisy = r.real("ratio_noisy");
  u.upsilon_noisy = r.real("upsilon_noisy");
  u.singular_values = r.reals("singular_values");
  u.gain = r.reals("gain");
  if (j.contains("true_gain")) u.true_gain = r.reals("true_gain");  // absent: nominal plant
  const Reader a(file, r.at("accuracy"));
  u.accuracy.gain_identified = a.boolean("gain_identified");
  u.accuracy.sigma_n_error = a.real("sigma_n_error");
  u.accuracy.weakest_angle_deg = a.real("weakest_angle_deg");
  u.accuracy.minor_signs_right = a.boolean("minor_signs_right");
  u.accuracy.met = a.boolean("met");
  if (j.contains("not_run")) u.not_run = r.string("not_run");  // absent: the unit was run
  if (j.contains("cv_peak_ratio")) {  // absent: no CV test limits known (open loop)
    u.cv_peak_ratio = r.real("cv_peak_ratio");
    u.cv_violation_rows = r.integer("cv_violation_rows");
  }
  if (!r.at("lengths").is_array()) r.wrong("lengths", "an array");
  for (const json& p : r.at("lengths")) {
    const Reader l(file, p);
    u.lengths.push_back(
        {static_cast<int>(l.integer("percent")), l.integer("samples"), l.boolean("met")});
  }
  return u;
}

void check_unit(const UnitResult& u, const Config& config, const Unit& unit, int outputs,
                int inputs, const std::filesystem::path& file) {
  const auto wrong = [&](const std::string& field, const std::string& value,
                         const std::string& expected) {
    throw std::runtime_error(file.string() + ": " + field + " = " + value + ", expected " +
                             expected);
  };
  const auto text = [](double v) { return json(v).dump(); };
  const std::string& design = config.designs.at(static_cast<std::size_t>(unit.design));
  if (u.design != design || u.seed != unit.seed) {
    wrong("design, seed", json(u.design).dump().substr(0, 60) + ", " + std::to_string(u.seed),
          json(design).dump() + ", " + std::to_string(unit.seed) + " (the unit of this file name)");
  }
  for (const PresetInfo& p : presets()) {
    if (p.acronym == design && p.number != u.number)
      wrong("number", std::to_string(u.number),
            std::to_string(p.number) + " (Table 6.1's for " + design + ")");
  }
  constexpr long long kMaxSamples = 100000000;  // the plan file's bound is far below
  if (u.samples < 1 || u.samples > kMaxSamples)
    wrong("samples", std::to_string(u.samples), "1 to " + std::to_string(kMaxSamples));
  if (!(u.sample_time_min > 0.0) || !std::isfinite(u.sample_time_min))
    wrong("sample_time_min", text(u.sample_time_min), "a number > 0 (minutes)");
  const auto gains = static_cast<std::size_t>(outputs * inputs);
  const auto directions = static_cast<std::size_t>(std::min(outputs, inputs));
  if (!u.singular_values.empty() && u.singular_values.size() != directions)
    wrong("singular_values", std::to_string(u.singular_values.size()) + " values",
          std::to_string(directions) + " (" + config.plant + ") or none");
  for (const double v : u.singular_values) {
    if (v < 0.0) wrong("singular_values", text(v), "values >= 0");
  }
  if (!u.gain.empty() && u.gain.size() != gains)
    wrong("gain", std::to_string(u.gain.size()) + " values",
          std::to_string(gains) + " (" + config.plant + "'s G(0)) or none");
  const bool perturbed = config.perturb_percent > 0.0;
  if (u.true_gain.size() != gains && (perturbed || !u.true_gain.empty()))
    wrong("true_gain", std::to_string(u.true_gain.size()) + " values",
          std::to_string(gains) + " (" + config.plant + "'s G(0) perturbed)" +
              (perturbed ? "" : " or none"));
  const double angle = u.accuracy.weakest_angle_deg;
  if (angle < 0.0 || angle > 90.0)
    wrong("accuracy.weakest_angle_deg", text(angle), "0 to 90 (degrees) or null");
  if (u.cv_violation_rows < 0 || u.cv_violation_rows > u.samples)
    wrong("cv_violation_rows", std::to_string(u.cv_violation_rows),
          "0 to the unit's " + std::to_string(u.samples));
  if (u.cv_peak_ratio < 0.0) wrong("cv_peak_ratio", text(u.cv_peak_ratio), "a number >= 0");
  const std::vector<int> grid = length_grid(config);
  if (u.lengths.size() != grid.size())
    wrong("lengths", std::to_string(u.lengths.size()) + " points",
          std::to_string(grid.size()) + " (the length grid of length_step_percent " +
              std::to_string(config.length_step_percent) + ")");
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const LengthPoint& p = u.lengths[k];
    const std::string at = "lengths[" + std::to_string(k) + "]";
    if (p.percent != grid[k])
      wrong(at + ".percent", std::to_string(p.percent), std::to_string(grid[k]));
    if (p.samples < 0 || p.samples > u.samples)
      wrong(at + ".samples", std::to_string(p.samples),
            "0 to the unit's " + std::to_string(u.samples));
  }
}

std::filesystem::path unit_path(const std::filesystem::path& dir, const Config& config,
                                const Unit& unit) {
  return dir / "units" / config.designs[static_cast<std::size_t>(unit.design)] /
         ("seed-" + std::to_string(unit.seed) + ".json");
}

std::string first_difference(const Config& found, const Config& expected) {
  json ja = config_json(found);
  json jb = config_json(expected);
  ja.erase("shard");
  jb.erase("shard");
  for (auto it = jb.begin(); it != jb.end(); ++it) {
    if (!ja.contains(it.key()) || ja.at(it.key()) != it.value()) {
      return it.key() + " = " + (ja.contains(it.key()) ? ja.at(it.key()).dump() : "missing") +
             ", expected " + it.value().dump();
    }
  }
  return {};
}

}  // namespace excite::host::montecarlo
