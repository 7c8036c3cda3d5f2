// SPDX-License-Identifier: MIT
#include "host/montecarlo/summary.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include "host/campaign/report_figures.hpp"
#include "host/design/case_studies.hpp"
#include "host/measures/accuracy.hpp"
#include "host/montecarlo/records.hpp"
#include "host/montecarlo/statistics.hpp"
#include "sim/library/perturb.hpp"

namespace excite::host::montecarlo {
namespace {

using nlohmann::json;

json spread_json(const std::vector<double>& values) {
  const Spread s = spread_of(values);
  return {{"median", json_number(s.median)},
          {"p10", json_number(s.p10)},
          {"p90", json_number(s.p90)},
          {"finite", s.finite},
          {"left_out", s.left_out}};
}

json share_json(int met, int of) {
  const Interval w = wilson95(met, of);
  return {{"met", met},
          {"of", of},
          {"share", of > 0 ? json(static_cast<double>(met) / of) : json(nullptr)},
          {"wilson95", {w.low, w.high}}};
}

template <class F>
std::vector<double> collect(const std::vector<const UnitResult*>& units, F figure) {
  std::vector<double> v;
  for (const UnitResult* u : units) v.push_back(figure(*u));
  return v;
}

// Per element of G(0): the nominal true gain, the spread of the identified one and of its
// error against the seed's true gain (the nominal one unless the plant was perturbed), and
// whether the median error is larger than the error's 10–90 % range is wide (a bias the noise
// does not explain: the model's structure or the identifier).
json gain_elements_json(const std::vector<const UnitResult*>& units, const Eigen::MatrixXd& truth) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  json elements = json::array();
  for (Eigen::Index i = 0; i < truth.rows(); ++i) {
    for (Eigen::Index j = 0; j < truth.cols(); ++j) {
      const auto at = static_cast<std::size_t>(i * truth.cols() + j);
      json e = spread_json(collect(
          units, [at](const UnitResult& u) { return at < u.gain.size() ? u.gain[at] : nan; }));
      e["output"] = i;
      e["input"] = j;
      e["true"] = truth(i, j);
      e["error"] = spread_json(collect(units, [&](const UnitResult& u) {
        const double true_gain = u.true_gain.empty()       ? truth(i, j)
                                 : at < u.true_gain.size() ? u.true_gain[at]
                                                           : nan;
        return at < u.gain.size() ? u.gain[at] - true_gain : nan;
      }));
      const json& error = e["error"];
      e["bias_exceeds_spread"] = error["median"].is_number() &&
                                 std::abs(error["median"].get<double>()) >
                                     error["p90"].get<double>() - error["p10"].get<double>();
      elements.push_back(e);
    }
  }
  return elements;
}

// The figures the verdicts compare, per unit: "better" is higher, or lower (of |value|).
struct VerdictMetric {
  const char* key;
  const char* label;
  bool higher_is_better;
  double (*value)(const UnitResult&);
};
const VerdictMetric kVerdictMetrics[] = {
    {"fit", "own fit [%]", true, [](const UnitResult& u) { return u.fit_avg; }},
    {"crossfit_worst", "worst cross-fit [%]", true,
     [](const UnitResult& u) { return u.crossfit_worst; }},
    {"ratio", "output balance, noise-free (ratio min/max, 1 = balanced)", true,
     [](const UnitResult& u) { return u.ratio; }},
    {"sigma_n_error_percent", "|error of sigma_n| [%]", false,
     [](const UnitResult& u) { return std::abs(100.0 * u.accuracy.sigma_n_error); }},
    {"weakest_direction_angle_deg", "angle of the weakest input direction v_n [deg]", false,
     [](const UnitResult& u) { return u.accuracy.weakest_angle_deg; }},
};

double median_of(const std::vector<double>& v) {
  return spread_of(v).median;
}

// +1: a better than b, −1: worse, 0: equal; kNotCompared: NaN on either side. (A plain int,
// not std::optional: GCC 12 -O1 sees the optional's value as maybe uninitialized.)
constexpr int kNotCompared = 2;
int compare(double a, double b, bool higher_is_better) {
  if (!std::isfinite(a) || !std::isfinite(b)) return kNotCompared;
  if (a == b) return 0;
  return (a > b) == higher_is_better ? 1 : -1;
}

// Directional designs (is_directional_design) against the others, per metric: the verdict by
// the median over all (design, seed) values of each group, and in how many seeds it holds
// (that seed's median over the group's designs compared the same way), and in how many seeds
// the best directional design beats the best other one.
json verdicts_json(const Config& config, const std::vector<UnitResult>& units) {
  json verdicts = json::array();
  bool any_directional = false, any_plain = false;
  for (const std::string& d : config.designs)
    (is_directional_design(d) ? any_directional : any_plain) = true;
  const bool both = any_directional && any_plain;
  for (const VerdictMetric& m : kVerdictMetrics) {
    json v = {
        {"metric", m.key}, {"label", m.label}, {"better", m.higher_is_better ? "higher" : "lower"}};
    std::vector<double> pooled[2];  // [0] others, [1] directional
    std::vector<std::vector<double>> by_seed[2];
    for (auto& b : by_seed) b.resize(static_cast<std::size_t>(config.seeds));
    for (const UnitResult& u : units) {
      const int g = is_directional_design(u.design) ? 1 : 0;
      const double x = m.value(u);
      pooled[g].push_back(x);
      by_seed[g][static_cast<std::size_t>(u.seed - config.first_seed)].push_back(x);
    }
    const double dir = median_of(pooled[1]), plain = median_of(pooled[0]);
    v["directional_median"] = json_number(dir);
    v["others_median"] = json_number(plain);
    const int overall = both ? compare(dir, plain, m.higher_is_better) : kNotCompared;
    v["verdict"] = overall == kNotCompared ? json(nullptr)
                   : overall > 0           ? json("directional better")
                   : overall < 0           ? json("directional not better")
                                           : json("equal");
    int holds = 0, compared = 0, best_better = 0, best_compared = 0;
    for (int s = 0; overall != kNotCompared && s < config.seeds; ++s) {
      const auto& d = by_seed[1][static_cast<std::size_t>(s)];
      const auto& o = by_seed[0][static_cast<std::size_t>(s)];
      const int seed_verdict = compare(median_of(d), median_of(o), m.higher_is_better);
      if (seed_verdict != kNotCompared) {
        ++compared;
        holds += seed_verdict == overall ? 1 : 0;
      }
      // The best of each group (finite values only).
      const auto best = [&](const std::vector<double>& values) {
        double b = std::numeric_limits<double>::quiet_NaN();
        for (const double x : values) {
          if (std::isfinite(x) && (!std::isfinite(b) || (x > b) == m.higher_is_better)) b = x;
        }
        return b;
      };
      const int best_verdict = compare(best(d), best(o), m.higher_is_better);
      if (best_verdict != kNotCompared) {
        ++best_compared;
        best_better += best_verdict > 0 ? 1 : 0;
      }
    }
    v["holds_in_seeds"] = share_json(holds, compared);
    v["best_directional_better_in_seeds"] = share_json(best_better, best_compared);
    verdicts.push_back(v);
  }
  return verdicts;
}

json design_json(const std::string& name, const std::vector<const UnitResult*>& units,
                 std::size_t inputs, const Eigen::MatrixXd& true_gain) {
  const UnitResult& first = *units.front();
  json j = {{"design", name},
            {"number", first.number},
            {"seeds", units.size()},
            {"samples", first.samples},
            {"sample_time_min", first.sample_time_min}};
  j["fit"] = spread_json(collect(units, [](const UnitResult& u) { return u.fit_avg; }));
  j["crossfit_worst"] =
      spread_json(collect(units, [](const UnitResult& u) { return u.crossfit_worst; }));
  j["ratio"] = spread_json(collect(units, [](const UnitResult& u) { return u.ratio; }));
  j["upsilon"] = spread_json(collect(units, [](const UnitResult& u) { return u.upsilon; }));
  j["ratio_noisy"] = spread_json(collect(units, [](const UnitResult& u) { return u.ratio_noisy; }));
  j["upsilon_noisy"] =
      spread_json(collect(units, [](const UnitResult& u) { return u.upsilon_noisy; }));
  json sv = json::array();
  for (std::size_t i = 0; i < inputs; ++i) {
    sv.push_back(spread_json(collect(units, [i](const UnitResult& u) {
      return i < u.singular_values.size() ? u.singular_values[i]
                                          : std::numeric_limits<double>::quiet_NaN();
    })));
  }
  j["singular_values"] = sv;
  j["gain_elements"] = gain_elements_json(units, true_gain);
  j["sigma_n_error_percent"] = spread_json(
      collect(units, [](const UnitResult& u) { return 100.0 * u.accuracy.sigma_n_error; }));
  j["weakest_direction_angle_deg"] =
      spread_json(collect(units, [](const UnitResult& u) { return u.accuracy.weakest_angle_deg; }));
  int met = 0, minors = 0, identified = 0;
  for (const UnitResult* u : units) {
    met += u->accuracy.met ? 1 : 0;
    minors += u->accuracy.minor_signs_right ? 1 : 0;
    identified += u->accuracy.gain_identified ? 1 : 0;
  }
  const int n = static_cast<int>(units.size());
  j["gain_identified"] = share_json(identified, n);
  j["minor_signs_right"] = share_json(minors, n);
  j["criterion"] = share_json(met, n);

  json lengths = json::array();
  std::vector<double> shares;
  for (std::size_t g = 0; g < first.lengths.size(); ++g) {
    int k = 0;
    for (const UnitResult* u : units) {
      if (u->lengths.size() != first.lengths.size() ||
          u->lengths[g].percent != first.lengths[g].percent) {
        throw std::runtime_error(name + " seed " + std::to_string(u->seed) +
                                 ": length grid differs from seed " + std::to_string(first.seed));
      }
      k += u->lengths[g].met ? 1 : 0;
    }
    json p = share_json(k, n);
    p["percent"] = first.lengths[g].percent;
    p["samples"] = first.lengths[g].samples;
    p["minutes"] = static_cast<double>(first.lengths[g].samples) * first.sample_time_min;
    lengths.push_back(p);
    shares.push_back(static_cast<double>(k) / n);
  }
  j["lengths"] = lengths;
  const std::optional<std::size_t> t90 = t90_index(shares);
  j["t90"] = t90 ? json{{"percent", lengths[*t90]["percent"]},
                        {"samples", lengths[*t90]["samples"]},
                        {"minutes", lengths[*t90]["minutes"]}}
                 : json(nullptr);
  return j;
}

std::string format(const char* pattern, double a, double b, double c) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

std::string spread_text(const json& s, const char* pattern) {
  return format(pattern, number_of(s["median"]), number_of(s["p10"]), number_of(s["p90"]));
}

}  // namespace

std::optional<std::size_t> t90_index(const std::vector<double>& shares) {
  std::optional<std::size_t> from;
  for (std::size_t g = shares.size(); g-- > 0;) {
    if (!(shares[g] >= kT90Share)) break;
    from = g;
  }
  return from;
}

namespace {

// The run's closed loop: its options as run.json keeps them (config_json), and a sentence.
json closed_loop_run_json(const Config& c) {
  const ClosedLoopConfig& l = c.closed_loop;
  const std::string model = l.model_perturb_percent > 0.0
                                ? "its model perturbed per seed within +-" +
                                      sim::percent_text(l.model_perturb_percent) +
                                      " % (every gain, time constant and delay)"
                                : "its model as the controller file gives it";
  json j = config_json(c)["closed_loop"];
  j["text"] =
      "closed loop in process under " + l.controller + ", " + model + "; " +
      (l.excitation == "mv"       ? "MV dither"
       : l.directions == "output" ? "setpoint excitation along the prior's output directions"
                                  : "setpoint excitation") +
      (l.excitation == "setpoint" && l.switching == "loop"
           ? " at the loop's pace ((4.2.3)'s tau_L the loop's along the weakest output "
             "direction)"
           : "") +
      (l.prbs_phase > 0
           ? ", the PRBS started " + std::to_string(l.prbs_phase) + " switching intervals in"
           : "") +
      (l.method == "direct"
           ? "; identified direct (the prediction-error fit with an AR or ARMA(1,1) "
             "noise model on the applied u, the test-length prefixes too)"
           : "; identified two-stage (the prediction-error fit with an AR or ARMA(1,1) "
             "noise model on u's part that r explains, the test-length prefixes too, "
             "stage 1 on the prefix alone)") +
      "; no cross-validation";
  return j;
}

// design_json over the units that were run; those not run (UnitResult::not_run) counted
// apart, with the first one's reason.
json ran_design_json(const std::string& name, const std::vector<const UnitResult*>& units,
                     std::size_t inputs, const Eigen::MatrixXd& true_gain) {
  std::vector<const UnitResult*> ran;
  std::string first_why;
  for (const UnitResult* u : units) {
    if (u->not_run.empty()) {
      ran.push_back(u);
    } else if (first_why.empty()) {
      first_why = "seed " + std::to_string(u->seed) + ": " + u->not_run;
    }
  }
  if (ran.empty()) throw std::runtime_error(name + ": no seed was run (" + first_why + ")");
  json j = design_json(name, ran, inputs, true_gain);
  int limited = 0, outside = 0;
  long long most_rows = 0;
  double largest = 0.0;
  for (const UnitResult* u : ran) {
    if (!std::isfinite(u->cv_peak_ratio)) continue;
    ++limited;
    outside += u->cv_violation_rows > 0 ? 1 : 0;
    most_rows = std::max(most_rows, u->cv_violation_rows);
    largest = std::max(largest, u->cv_peak_ratio);
  }
  if (limited > 0) {  // closed loop with CV test limits
    j["cv_limits"] = {
        {"seeds_outside", outside},
        {"of", limited},
        {"peak_ratio",
         spread_json(collect(ran, [](const UnitResult& u) { return u.cv_peak_ratio; }))},
        {"largest_peak_ratio", largest},
        {"max_rows_outside", most_rows}};
  }
  if (ran.size() < units.size())
    j["not_run"] = {{"seeds", units.size() - ran.size()}, {"first", first_why}};
  return j;
}

}  // namespace

json summary_json(const Config& config, const std::vector<UnitResult>& units) {
  const TruePlant truth = true_plant_of(case_study(config.plant).gain);
  const auto inputs = static_cast<std::size_t>(truth.gain.singular_values.size());
  json true_sv = json::array();
  for (Eigen::Index i = 0; i < truth.gain.singular_values.size(); ++i)
    true_sv.push_back(truth.gain.singular_values(i));
  json designs = json::array();
  for (std::size_t d = 0; d < config.designs.size(); ++d) {
    std::vector<const UnitResult*> of_design;
    for (const UnitResult& u : units) {
      if (u.design == config.designs[d]) of_design.push_back(&u);
    }
    if (of_design.size() != static_cast<std::size_t>(config.seeds)) {
      throw std::runtime_error(config.designs[d] + ": " + std::to_string(of_design.size()) +
                               " seeds finished, expected " + std::to_string(config.seeds));
    }
    designs.push_back(ran_design_json(config.designs[d], of_design, inputs, truth.gain.gain));
  }
  Config c = config;
  c.shard = {};
  json j;
  j["format"] = "excite montecarlo summary v1";
  j["run"] = {{"plant", c.plant},
              {"designs", c.designs},
              {"seeds", c.seeds},
              {"first_seed", c.first_seed},
              {"noise_variance", c.noise_variance},
              {"noise_seed", "experiment e of seed s: 100*s + e (excite campaign --seed 100s)"},
              {"length_step_percent", c.length_step_percent},
              {"perturb_percent", c.perturb_percent},
              {"true_plant", c.perturb_percent > 0.0
                                 ? "perturbed per seed: every element's gain, every time "
                                   "constant and every delay within +-" +
                                       sim::percent_text(c.perturb_percent) +
                                       " % of the nominal plant's (sim/library/perturb.hpp); "
                                       "the designs use the nominal plant, the criterion, the "
                                       "balance and the gain errors the seed's perturbed one"
                                 : "the nominal plant in every seed"}};
  if (c.closed_loop.on()) j["run"]["closed_loop"] = closed_loop_run_json(c);
  j["criterion"] = {
      {"text",
       "identified G(0): every principal minor's sign right, sigma_n within 20 %, the weakest "
       "input direction v_n within 10 degrees (sign ignored)"},
      {"sigma_n_tolerance", kSigmaTolerance},
      {"angle_tolerance_deg", kAngleToleranceDeg}};
  j["t90_definition"] =
      "the shortest grid length L (percent of the run) such that the share of seeds meeting "
      "the criterion on the first L of the run is >= 90 % at L and at every longer grid length; "
      "null when the whole run's share is below 90 %";
  j["spread"] =
      "median and 10-90 % range (linear interpolation, type 7) over the seeds; "
      "finite values only";
  j["intervals"] = "Wilson score interval at 95 %";
  j["bias_definition"] =
      "gain_elements[].bias_exceeds_spread: |median error| > p90 - p10 of the error (identified "
      "minus the seed's true gain) over the seeds: an error the noise does not explain (the "
      "model structure or the identifier)";
  j["verdict_definition"] =
      "directional designs against the others per metric: the verdict compares the medians over "
      "all (design, seed) values of each group; holds_in_seeds counts the seeds in which the "
      "same comparison of that seed's medians over the group's designs gives the same verdict; "
      "best_directional_better_in_seeds the seeds in which the best directional design beats "
      "the best other one. |sigma_n error| and the v_n angle: lower is better";
  j["true_singular_values"] = true_sv;
  j["designs"] = designs;
  std::vector<UnitResult> ran;
  for (const UnitResult& u : units)
    if (u.not_run.empty()) ran.push_back(u);
  j["verdicts"] = verdicts_json(c, ran);
  return j;
}

namespace {

// One line per design: fit, worst cross-fit, ratio, σ_n and v_n errors (median [10-90 %]),
// the share meeting the criterion with its Wilson interval, and T90.
std::string designs_table(const json& summary) {
  std::string out;
  char line[512];
  std::snprintf(line, sizeof line, "%-15s %-22s %-22s %-22s %-22s %-22s %-24s %s\n", "design",
                "fit % [10-90]", "worst cross-fit %", "ratio (noise-free)", "sigma_n error %",
                "v_n angle deg", "criterion met [95 %]", "T90");
  out += line;
  for (const json& d : summary["designs"]) {
    const json& c = d["criterion"];
    char share[64];
    std::snprintf(share, sizeof share, "%d/%d [%.2f-%.2f]", c["met"].get<int>(), c["of"].get<int>(),
                  c["wilson95"][0].get<double>(), c["wilson95"][1].get<double>());
    std::string t90 = "none";
    if (!d["t90"].is_null()) {
      char text[64];
      std::snprintf(text, sizeof text, "%d %% (%.0f min)", d["t90"]["percent"].get<int>(),
                    d["t90"]["minutes"].get<double>());
      t90 = text;
    }
    std::snprintf(line, sizeof line, "%-15s %-22s %-22s %-22s %-22s %-22s %-24s %s\n",
                  d["design"].get<std::string>().c_str(),
                  spread_text(d["fit"], "%.1f [%.1f-%.1f]").c_str(),
                  spread_text(d["crossfit_worst"], "%.1f [%.1f-%.1f]").c_str(),
                  spread_text(d["ratio"], "%.3f [%.3f-%.3f]").c_str(),
                  spread_text(d["sigma_n_error_percent"], "%.1f [%.1f-%.1f]").c_str(),
                  spread_text(d["weakest_direction_angle_deg"], "%.1f [%.1f-%.1f]").c_str(), share,
                  t90.c_str());
    out += line;
  }
  for (const json& d : summary["designs"]) {
    if (!d.contains("cv_limits")) continue;
    const json& l = d["cv_limits"];
    out += "  " + d["design"].get<std::string>() +
           ": CV test limits: " + std::to_string(l["seeds_outside"].get<int>()) + " of " +
           std::to_string(l["of"].get<int>()) + " seeds outside them (at most " +
           std::to_string(l["max_rows_outside"].get<long long>()) + " rows); peak |CV| / limit " +
           spread_text(l["peak_ratio"], "%.2f [%.2f-%.2f]") + "\n";
  }
  for (const json& d : summary["designs"]) {
    if (!d.contains("not_run")) continue;
    out += "  " + d["design"].get<std::string>() + ": " +
           std::to_string(d["not_run"]["seeds"].get<int>()) +
           " seeds not run, not in its shares or T90 (first: " +
           d["not_run"]["first"].get<std::string>() + ")\n";
  }
  return out;
}

// Per design, the G(0) elements whose median is biased beyond their spread.
std::string biased_elements(const json& summary) {
  std::string out =
      "G(0) elements whose median is off the true gain by more than their 10-90 % range "
      "(bias, not noise):\n";
  char line[512];
  for (const json& d : summary["designs"]) {
    std::string biased;
    for (const json& e : d["gain_elements"]) {
      if (!e["bias_exceeds_spread"].get<bool>()) continue;
      const json& error = e["error"];
      std::snprintf(line, sizeof line, " g%d%d %.3g (true %.3g, median error %+.3g, range %.3g)",
                    e["output"].get<int>() + 1, e["input"].get<int>() + 1,
                    e["median"].get<double>(), e["true"].get<double>(),
                    error["median"].get<double>(),
                    error["p90"].get<double>() - error["p10"].get<double>());
      biased += line;
    }
    out += "  " + d["design"].get<std::string>() + ":" + (biased.empty() ? " none" : biased) + "\n";
  }
  return out;
}

// The directional designs against the others, one line per verdict.
std::string verdict_lines(const json& summary) {
  std::string out =
      "directional designs against the others (verdict by median; seeds in which it holds; "
      "seeds in which the best directional design beats the best other):\n";
  char line[512];
  for (const json& v : summary["verdicts"]) {
    if (v["verdict"].is_null()) {
      out += "  " + v["label"].get<std::string>() + ": - (needs designs of both groups)\n";
      continue;
    }
    std::snprintf(line, sizeof line,
                  "  %s: %s (%.4g against %.4g); holds in %d of %d seeds; "
                  "best directional better in %d of %d\n",
                  v["label"].get<std::string>().c_str(), v["verdict"].get<std::string>().c_str(),
                  number_of(v["directional_median"]), number_of(v["others_median"]),
                  v["holds_in_seeds"]["met"].get<int>(), v["holds_in_seeds"]["of"].get<int>(),
                  v["best_directional_better_in_seeds"]["met"].get<int>(),
                  v["best_directional_better_in_seeds"]["of"].get<int>());
    out += line;
  }
  return out;
}

// Per design, the share meeting the criterion at each test length of the grid.
std::string shares_by_length(const json& summary) {
  std::string out =
      "share of seeds meeting the criterion by test length (percent of the run: share):\n";
  char line[512];
  for (const json& d : summary["designs"]) {
    out += "  " + d["design"].get<std::string>() + ":";
    for (const json& p : d["lengths"]) {
      std::snprintf(line, sizeof line, " %d:%.2f", p["percent"].get<int>(),
                    p["share"].is_null() ? 0.0 : p["share"].get<double>());
      out += line;
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string summary_text(const json& summary) {
  const json& run = summary["run"];
  std::string out = "plant " + run["plant"].get<std::string>() + ", " +
                    std::to_string(run["seeds"].get<int>()) + " seeds from " +
                    std::to_string(run["first_seed"].get<std::uint64_t>()) +
                    "; criterion: " + summary["criterion"]["text"].get<std::string>() + "\n";
  if (run.value("perturb_percent", 0.0) > 0.0)
    out += "true plant: " + run["true_plant"].get<std::string>() + "\n";
  if (run.contains("closed_loop"))
    out += "controller on: " + run["closed_loop"]["text"].get<std::string>() + "\n";
  return out + designs_table(summary) + biased_elements(summary) + verdict_lines(summary) +
         shares_by_length(summary);
}

}  // namespace excite::host::montecarlo
