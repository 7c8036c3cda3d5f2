// SPDX-License-Identifier: MIT
#include "host/adaptive/decision_log.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace excite::host {
namespace {

nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nullptr;
}

nlohmann::json numbers(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) a.push_back(number(v(i)));
  return a;
}

std::string name_of(const std::vector<std::string>& names, int i, const char* prefix) {
  return i < static_cast<int>(names.size()) ? names[static_cast<std::size_t>(i)]
                                            : prefix + std::to_string(i + 1);
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  char text[40];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

std::string significant(double v) {
  if (!std::isfinite(v)) return "-";
  char text[40];
  std::snprintf(text, sizeof text, "%.4g", v);
  return text;
}

}  // namespace

nlohmann::json segment_event(const SegmentDecision& s, double sample_time_min) {
  return {{"event", "segment"},
          {"index", s.index},
          {"first_row", s.first_row},
          {"start_min", static_cast<double>(s.first_row) * sample_time_min},
          {"rows", s.rows},
          {"minutes", s.rows * sample_time_min},
          {"kind", s.directional ? "directions" : "plain"},
          {"from_estimate", s.from_estimate >= 0 ? nlohmann::json(s.from_estimate) : nullptr},
          {"weights", numbers(s.weights)},
          {"scale", s.scale},
          {"why", s.why}};
}

nlohmann::json estimate_event(const Reestimate& e, int index) {
  nlohmann::json j = {{"event", "estimate"},
                      {"index", index},
                      {"after_segment", e.after_segment},
                      {"samples", e.samples},
                      {"length_min", e.length_min}};
  const IdentifiedModel& m = e.result.model;
  nlohmann::json grades = nlohmann::json::array();
  for (int o = 0; o < m.outputs; ++o) {
    nlohmann::json row = nlohmann::json::array();
    for (int i = 0; i < m.inputs; ++i) row.push_back(to_string(m.element(o, i).grade));
    grades.push_back(row);
  }
  j["grades"] = grades;
  j["colour"] = numbers(e.colour);
  if (e.uncertainty) {
    const GainUncertainty& u = *e.uncertainty;
    j["singular_values"] = numbers(u.singular_values);
    j["singular_value_se"] = numbers(u.singular_value_se);
    j["input_angle_se_deg"] = numbers(u.input_angle_se_deg);
    j["output_angle_se_deg"] = numbers(u.output_angle_se_deg);
    j["sign_uncertain_minors"] = u.sign_uncertain_minors;
  } else {
    for (const char* key : {"singular_values", "singular_value_se", "input_angle_se_deg",
                            "output_angle_se_deg", "sign_uncertain_minors"})
      j[key] = nullptr;
  }
  const Confidence& c = e.confidence;
  j["need"] = {{"overall", number(c.need)},
               {"sigma_n", number(c.sigma_n_need)},
               {"angle", number(c.angle_need)},
               {"minor", number(c.minor_need)},
               {"per_direction", numbers(c.direction_need)},
               {"z", number(c.z)},
               {"noise_level_dof", number(c.noise_level_dof)}};
  j["met"] = c.met;
  j["missing"] = c.missing;
  j["predicted_stop_min"] = e.predicted_stop_min ? number(*e.predicted_stop_min) : nullptr;
  return j;
}

nlohmann::json stop_event(const AdaptiveResult& r) {
  return {{"event", "stop"},
          {"criterion_met", r.criterion_met},
          {"reason", r.stop_reason},
          {"length_min", r.length_min()},
          {"segments", r.segments.size()},
          {"estimates", r.estimates.size()},
          {"rows_outside_limits", r.rows_outside_limits}};  // per output; [] without limits
}

std::string operator_view(const AdaptiveResult& r, const std::vector<std::string>& inputs,
                          const std::vector<std::string>& outputs, bool pending) {
  std::ostringstream v;
  v << "excite test at " << fixed(r.length_min(), 0) << " min: " << r.segments.size()
    << " segment(s), " << r.estimates.size() << " estimate(s)\n";
  if (r.estimates.empty()) {
    v << "  no estimate yet (the record is still too short to identify)\n";
  } else {
    const Reestimate& e = r.estimates.back();
    v << "  estimate at " << fixed(e.length_min, 0) << " min\n";
    if (e.uncertainty) {
      const GainUncertainty& u = *e.uncertainty;
      v << "  direction  sigma          +- SE        v angle SE deg  w angle SE deg  need\n";
      for (Eigen::Index i = 0; i < u.singular_values.size(); ++i) {
        char line[160];
        std::snprintf(line, sizeof line, "  %-9ld  %-13s  %-11s  %-14s  %-14s  %s\n",
                      static_cast<long>(i + 1), significant(u.singular_values(i)).c_str(),
                      significant(u.singular_value_se(i)).c_str(),
                      fixed(u.input_angle_se_deg(i), 2).c_str(),
                      fixed(u.output_angle_se_deg(i), 2).c_str(),
                      e.confidence.direction_need.size() > i
                          ? fixed(e.confidence.direction_need(i), 2).c_str()
                          : "-");
        v << line;
      }
      v << "  principal minors of uncertain sign: " << u.sign_uncertain_minors << "\n";
    } else {
      v << "  no G(0) uncertainty: " << e.confidence.missing << "\n";
    }
    const IdentifiedModel& m = e.result.model;
    v << "  grades (rows: outputs, columns: inputs)\n  " << std::string(10, ' ');
    for (int i = 0; i < m.inputs; ++i) {
      char cell[24];
      std::snprintf(cell, sizeof cell, " %-8.8s", name_of(inputs, i, "u").c_str());
      v << cell;
    }
    v << "\n";
    for (int o = 0; o < m.outputs; ++o) {
      char head[24];
      std::snprintf(head, sizeof head, "  %-10.10s", name_of(outputs, o, "y").c_str());
      v << head;
      for (int i = 0; i < m.inputs; ++i) v << " " << to_string(m.element(o, i).grade) << "       ";
      v << "\n";
    }
    v << "  stop rule: need " << fixed(e.confidence.need, 2) << " (<= 1 to stop; sigma_n "
      << fixed(e.confidence.sigma_n_need, 2) << ", v_n angle " << fixed(e.confidence.angle_need, 2)
      << ", minors " << fixed(e.confidence.minor_need, 2) << ")";
    if (e.predicted_stop_min) {
      v << "; predicted stop at " << fixed(*e.predicted_stop_min, 0) << " min";
    }
    v << "\n";
  }
  for (std::size_t j = 0; j < r.rows_outside_limits.size(); ++j) {
    if (r.rows_outside_limits[j] == 0) continue;
    v << "  limits: " << outputs.at(j) << " measured outside its limits in "
      << r.rows_outside_limits[j] << " rows (furthest "
      << fixed(r.worst_outside_limits(static_cast<Eigen::Index>(j)), 3) << ")\n";
  }
  if (!r.stop_reason.empty()) {
    v << "  stopped: " << r.stop_reason << "\n";
  } else if (pending && !r.segments.empty()) {
    const SegmentDecision& s = r.segments.back();
    v << "  next segment " << s.index << " (" << s.rows << " rows from "
      << fixed(static_cast<double>(s.first_row) * r.sample_time_min, 0) << " min): " << s.why
      << "\n";
  }
  return v.str();
}

nlohmann::json study_json(const StudyResult& s) {
  const StudyOptions& o = s.options;
  nlohmann::json seeds = nlohmann::json::array();
  for (const SeedOutcome& x : s.seeds) {
    nlohmann::json met = nlohmann::json::array();
    for (const bool b : x.estimate_met) met.push_back(b);
    nlohmann::json need = nlohmann::json::array();
    for (const double d : x.estimate_need) need.push_back(number(d));
    seeds.push_back({{"seed", x.seed},
                     {"not_run", x.not_run},
                     {"stopped_by_rule", x.stopped_by_rule},
                     {"stop_min", x.stop_min},
                     {"stop_reason", x.stop_reason},
                     {"estimate_min", x.estimate_min},
                     {"estimate_met", met},
                     {"estimate_need", need},
                     {"estimate_missing", x.estimate_missing},
                     {"true_sigma_n", x.true_sigma_n},
                     {"met_at_stop", x.met_at_stop},
                     {"sigma_n_error_at_stop", number(x.sigma_n_error_at_stop)},
                     {"angle_at_stop_deg", number(x.angle_at_stop_deg)},
                     {"segments", x.segments},
                     {"directional_segments", x.directional_segments},
                     {"smallest_scale", x.smallest_scale},
                     {"peak_limit_ratio", x.peak_limit_ratio},
                     {"violated", x.violated}});
  }
  const auto t90 = [&](const std::optional<std::size_t>& i) {
    return i ? nlohmann::json(s.grid_min[*i]) : nlohmann::json(nullptr);
  };
  nlohmann::json closed_loop = nullptr;  // open loop
  if (const auto& c = o.closed_loop) {
    closed_loop = {{"controller", c->controller},
                   {"estimate", c->two_stage ? "two-stage" : "direct"},
                   {"limit_fraction", c->limit_fraction},
                   {"mv_fraction", c->mv_fraction},
                   {"first_segment", c->prior_directions ? "output directions" : "plain"},
                   {"prbs_phase", c->prbs_phase},
                   {"disturbance_std", c->disturbance_std},
                   {"disturbance_tau_min", c->disturbance_tau_min}};
    if (const auto& speed = s.loop_speed) {
      closed_loop["loop_time_constant_min"] = speed->time_constant_min;
      closed_loop["loop_time_constant_reached"] = speed->reached;
    }
  }
  return {{"format", "excite adaptive study v1"},
          {"plant", o.plant},
          {"closed_loop", closed_loop},
          {"seeds", o.seeds},
          {"not_run", s.not_run},
          {"first_seed", o.first_seed},
          {"perturb_percent", o.perturb_percent},
          {"segment_min", s.segment_min},
          {"tau_low_min", s.tau_low_min},
          {"switch_time_min", s.switch_time_min},
          {"grid_min", s.grid_min},
          {"share_stopped_met", s.share_stopped_met},
          {"share_met", s.share_met},
          {"t90_stop_min", t90(s.t90_stop)},
          {"t90_oracle_min", t90(s.t90_oracle)},
          {"per_seed", seeds}};
}

std::string study_text(const StudyResult& s) {
  std::ostringstream t;
  int stopped = 0, wrong = 0, violated = 0;
  for (const SeedOutcome& x : s.seeds) {
    if (x.stopped_by_rule) ++stopped;
    if (x.stopped_by_rule && !x.met_at_stop) ++wrong;
    if (x.violated) ++violated;
  }
  const auto t90 = [&](const std::optional<std::size_t>& i) {
    return i ? fixed(s.grid_min[*i], 0) + " min" : std::string("none");
  };
  t << "adaptive test on " << s.options.plant << ", " << s.options.seeds << " seeds from "
    << s.options.first_seed << ", segments of " << fixed(s.segment_min, 0) << " min";
  if (s.options.perturb_percent > 0.0)
    t << ", plant perturbed +-" << s.options.perturb_percent << " %";
  if (const auto& c = s.options.closed_loop) {
    t << "\n  closed loop: r on the CV setpoints under " << c->controller << " at "
      << c->limit_fraction << " of the CV limits, the " << (c->two_stage ? "two-stage" : "direct")
      << " estimate";
    if (c->prior_directions) t << ", the first segment along the prior's output directions";
    if (c->prbs_phase > 0) t << ", the PRBS from switching interval " << c->prbs_phase;
    if (c->disturbance_std > 0.0)
      t << ", coloured disturbance " << c->disturbance_std << " (tau " << c->disturbance_tau_min
        << " min)";
    if (const auto& speed = s.loop_speed) {
      t << "\n  the loop follows a switch of r along the prior's weakest output direction in "
        << (speed->reached ? "" : "more than ") << fixed(speed->time_constant_min, 0)
        << " min (63 %, on the controller's model): PRBS T_sw = " << fixed(s.switch_time_min, 0)
        << " min by (4.2.3) with tau_L = " << fixed(s.tau_low_min, 0) << " min";
    } else {
      t << "\n  PRBS T_sw = " << fixed(s.switch_time_min, 0)
        << " min by (4.2.3) with the plant's tau_L = " << fixed(s.tau_low_min, 0) << " min";
    }
    if (s.not_run > 0)
      t << "\n  not run: " << s.not_run << " of " << s.options.seeds
        << " seeds (the controller refused the seed's plant; the shares are over the "
        << s.options.seeds - s.not_run << " run)";
  }
  t << "\n  stopped by the rule: " << stopped << " of " << s.options.seeds
    << "; of those, the model misses the criterion against the truth: " << wrong
    << "\n  CV limit violations (noise-free outputs): " << violated << " of " << s.options.seeds
    << "\n  T90 (stopped with a good model): " << t90(s.t90_stop)
    << "\n  T90 (oracle, the model in force): " << t90(s.t90_oracle) << "\n  length min: ";
  for (std::size_t i = 0; i < s.grid_min.size(); ++i) {
    t << fixed(s.grid_min[i], 0) << ":" << fixed(s.share_stopped_met[i], 2) << "/"
      << fixed(s.share_met[i], 2) << " ";
  }
  t << "(stopped-good / in force)\n";
  return t.str();
}

}  // namespace excite::host
