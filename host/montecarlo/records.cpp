// SPDX-License-Identifier: MIT
#include "host/montecarlo/records.hpp"

#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>

namespace excite::host::montecarlo {
namespace {

using nlohmann::json;

json number(double v) {
  return std::isfinite(v) ? json(v) : json(nullptr);
}

std::string text_of(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error(file.string() + ": cannot be read");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

json parse(const std::filesystem::path& file) {
  try {
    return json::parse(text_of(file));
  } catch (const json::parse_error& e) {
    throw std::runtime_error(file.string() + ": not JSON (" + e.what() + ")");
  }
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
      throw std::runtime_error(file_.string() + ": " + key + " missing, expected a value");
    return object_.at(key);
  }
  [[noreturn]] void wrong(const char* key, const char* expected) const {
    throw std::runtime_error(file_.string() + ": " + key + " = " + at(key).dump() + ", expected " +
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
    return v.get<long long>();
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
          {"sigma_n_error", number(a.sigma_n_error)},
          {"weakest_angle_deg", number(a.weakest_angle_deg)},
          {"minor_signs_right", a.minor_signs_right},
          {"met", a.met}};
}

}  // namespace

json config_json(const Config& c) {
  return {{"format", "excite montecarlo run v1"},
          {"plant", c.plant},
          {"designs", c.designs},
          {"seeds", c.seeds},
          {"first_seed", c.first_seed},
          {"noise_variance", c.noise_variance},
          {"length_step_percent", c.length_step_percent},
          {"perturb_percent", c.perturb_percent},
          {"shard", std::to_string(c.shard.index) + "/" + std::to_string(c.shard.count)}};
}

Config read_config(const std::filesystem::path& file) {
  const json j = parse(file);
  const Reader r(file, j);
  if (r.string("format") != "excite montecarlo run v1")
    r.wrong("format", "\"excite montecarlo run v1\"");
  Config c;
  c.plant = r.string("plant");
  if (!r.at("designs").is_array()) r.wrong("designs", "an array of design names");
  for (const json& d : r.at("designs")) {
    if (!d.is_string()) r.wrong("designs", "an array of design names");
    c.designs.push_back(d.get<std::string>());
  }
  c.seeds = static_cast<int>(r.integer("seeds"));
  c.first_seed = r.unsigned_integer("first_seed");
  c.noise_variance = r.real("noise_variance");
  c.length_step_percent = static_cast<int>(r.integer("length_step_percent"));
  // Absent in the folders of runs before --perturb: the nominal plant.
  if (j.contains("perturb_percent")) c.perturb_percent = r.real("perturb_percent");
  try {
    c.shard = parse_shard(r.string("shard"));
  } catch (const std::invalid_argument&) {
    r.wrong("shard", "i/N with 1 <= i <= N");
  }
  return c;
}

json unit_json(const UnitResult& u) {
  json lengths = json::array();
  for (const LengthPoint& p : u.lengths)
    lengths.push_back({{"percent", p.percent}, {"samples", p.samples}, {"met", p.met}});
  json sv = json::array();
  for (const double v : u.singular_values) sv.push_back(number(v));
  json gain = json::array();
  for (const double v : u.gain) gain.push_back(number(v));
  json true_gain = json::array();
  for (const double v : u.true_gain) true_gain.push_back(number(v));
  return {{"design", u.design},
          {"number", u.number},
          {"seed", u.seed},
          {"samples", u.samples},
          {"sample_time_min", u.sample_time_min},
          {"fit_avg", number(u.fit_avg)},
          {"crossfit_avg", number(u.crossfit_avg)},
          {"crossfit_worst", number(u.crossfit_worst)},
          {"ratio", number(u.ratio)},
          {"upsilon", number(u.upsilon)},
          {"ratio_noisy", number(u.ratio_noisy)},
          {"upsilon_noisy", number(u.upsilon_noisy)},
          {"singular_values", sv},
          {"gain", gain},
          {"true_gain", true_gain},
          {"accuracy", accuracy_json(u.accuracy)},
          {"lengths", lengths}};
}

UnitResult read_unit(const std::filesystem::path& file) {
  const json j = parse(file);
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
  if (!r.at("lengths").is_array()) r.wrong("lengths", "an array");
  for (const json& p : r.at("lengths")) {
    const Reader l(file, p);
    u.lengths.push_back(
        {static_cast<int>(l.integer("percent")), l.integer("samples"), l.boolean("met")});
  }
  return u;
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
