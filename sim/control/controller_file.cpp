// SPDX-License-Identifier: MIT
#include "sim/control/controller_file.hpp"

#include <cmath>
#include <tuple>

#include "base/config/document.hpp"
#include "base/config/table.hpp"

namespace excite::sim::control {
namespace {

// [lo, hi] with lo < hi (and lo ≤ 0 ≤ hi for a zone about the setpoint).
std::pair<double, double> interval(const config::Table& t, std::string_view key, bool about_zero) {
  const std::vector<double> v = t.numbers(key);
  const std::string what = about_zero
                               ? "[low, high] about the setpoint with low <= 0 <= high, low < high"
                               : "[low, high] with low < high";
  if (v.size() != 2 || !(v[0] < v[1]) || (about_zero && (v[0] > 0.0 || v[1] < 0.0))) {
    std::string written = "[";
    for (std::size_t i = 0; i < v.size(); ++i) {
      written += (i == 0 ? "" : ", ") + config::format_number(v[i]);
    }
    t.fail(key, written + "]", what);
  }
  return {v[0], v[1]};
}

MvSettings read_mv(const config::Table& t, ControllerKind kind) {
  if (kind == ControllerKind::dmc) {
    t.only_keys({"min", "max", "max_move", "move_suppression"});
  } else {
    t.only_keys({"min", "max", "max_move"});
  }
  MvSettings m;
  m.min = t.number("min").value_or(-kUnlimited);
  m.max = t.number("max").value_or(kUnlimited);
  if (!(m.min < m.max)) {
    t.fail("max", config::describe(*t.get("max")),
           "a number above min (" + config::format_number(m.min) + ")");
  }
  m.max_move = t.positive("max_move").value_or(kUnlimited);
  if (kind == ControllerKind::dmc)
    m.move_suppression = t.positive("move_suppression").value_or(1.0);
  return m;
}

CvSettings read_cv(const config::Table& t) {
  t.only_keys({"weight", "zone", "limits"});
  CvSettings c;
  c.weight = t.non_negative("weight").value_or(1.0);
  if (t.has("zone")) {
    c.zone = true;
    std::tie(c.zone_low, c.zone_high) = interval(t, "zone", true);
  }
  if (t.has("limits")) std::tie(c.limit_low, c.limit_high) = interval(t, "limits", false);
  return c;
}

}  // namespace

ControllerFile controller_from_toml(std::string_view text, std::string_view source) {
  const toml::table doc = config::parse(text, source);
  const config::Table root(doc, "", source);
  ControllerFile file;
  file.source = std::string(source);
  const auto kind = root.choice("kind", {"dmc", "pi"});
  if (!kind) root.fail_missing("kind", "\"dmc\" or \"pi\"");
  file.kind = *kind == "dmc" ? ControllerKind::dmc : ControllerKind::pi;
  if (file.kind == ControllerKind::dmc) {
    root.only_keys({"kind", "sample_time_min", "model", "dmc", "mv", "cv"});
  } else {
    root.only_keys({"kind", "sample_time_min", "model", "mv", "pairing"});
  }
  const auto T = root.positive("sample_time_min", "minutes");
  if (!T) root.fail_missing("sample_time_min", "a sample time > 0 minutes");
  file.sample_time_min = *T;

  const config::Table model = root.required_table("model", "a [model] table");
  model.only_keys({"plant", "model_file", "probe_step", "delay_samples"});
  file.model.plant = model.text("plant").value_or("");
  file.model.model_file = model.text("model_file").value_or("");
  if (file.model.plant.empty() == file.model.model_file.empty()) {
    if (file.model.plant.empty()) {
      model.fail_missing("plant", "a plant name, a plant file (.toml) or model_file = MODEL.json");
    }
    model.fail("model_file", config::describe(*model.get("model_file")),
               "either plant or model_file, not both");
  }
  file.model.probe_step = model.positive("probe_step").value_or(1.0);
  file.model.delay_samples = static_cast<int>(model.integer("delay_samples", 0, 1000).value_or(0));

  if (file.kind == ControllerKind::dmc) {
    const config::Table dmc = root.required_table("dmc", "a [dmc] table");
    dmc.only_keys({"prediction_horizon", "control_horizon", "slack_weight", "max_qp_iterations"});
    file.dmc.prediction_horizon =
        static_cast<int>(dmc.required_integer("prediction_horizon", 1, 100000));
    file.dmc.control_horizon = static_cast<int>(
        dmc.required_integer("control_horizon", 1, file.dmc.prediction_horizon,
                             "an integer 1.." + std::to_string(file.dmc.prediction_horizon) +
                                 " (at most prediction_horizon)"));
    file.dmc.slack_weight = dmc.positive("slack_weight").value_or(1e4);
    file.dmc.max_qp_iterations =
        static_cast<int>(dmc.integer("max_qp_iterations", 1, 100000).value_or(100));
    for (const config::Table& t : root.tables("cv")) file.dmc.cv.push_back(read_cv(t));
    file.cv_given = !file.dmc.cv.empty();
  } else {
    const std::vector<config::Table> pairs = root.tables("pairing");
    if (pairs.empty())
      root.fail_missing("pairing", "one [[pairing]] per loop (cv, mv, kc, ti_min)");
    for (const config::Table& t : pairs) {
      t.only_keys({"cv", "mv", "kc", "ti_min"});
      PiLoop l;
      l.cv = static_cast<int>(t.required_integer("cv", 1, 1000, "a CV number 1.. (1-based)")) - 1;
      l.mv = static_cast<int>(t.required_integer("mv", 1, 1000, "an MV number 1.. (1-based)")) - 1;
      l.gain = t.required_number("kc");
      if (l.gain == 0.0) t.fail("kc", config::describe(*t.get("kc")), "a gain other than 0");
      const auto ti = t.positive("ti_min", "minutes");
      if (!ti) t.fail_missing("ti_min", "an integral time > 0 minutes");
      l.integral_min = *ti;
      file.pairing.push_back(l);
    }
  }
  for (const config::Table& t : root.tables("mv")) file.dmc.mv.push_back(read_mv(t, file.kind));
  file.mv_given = !file.dmc.mv.empty();
  return file;
}

ControllerFile load_controller_file(const std::filesystem::path& path) {
  ControllerFile file = controller_from_toml(config::read_file(path), path.string());
  const std::filesystem::path plant = file.model.plant;
  if (plant.extension() == ".toml" && plant.is_relative()) {
    file.model.plant = (path.parent_path() / plant).string();
  }
  const std::filesystem::path model = file.model.model_file;
  if (!model.empty() && model.is_relative()) {
    file.model.model_file = (path.parent_path() / model).string();
  }
  return file;
}

}  // namespace excite::sim::control
