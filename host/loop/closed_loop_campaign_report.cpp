// SPDX-License-Identifier: MIT
#include "host/loop/closed_loop_campaign_report.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "host/loop/closed_loop_campaign_figures.hpp"
#include "host/output/html_page.hpp"
#include "host/output/whole_file.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

nlohmann::json gain_rows(const IdentifiedModel& m, bool std_errors) {
  nlohmann::json rows = nlohmann::json::array();
  for (int o = 0; o < m.outputs; ++o) {
    nlohmann::json row = nlohmann::json::array();
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      const double v = std_errors ? e.std_error.gain : e.value.static_gain();
      row.push_back(e.estimated() && std::isfinite(v) ? nlohmann::json(v) : nlohmann::json());
    }
    rows.push_back(row);
  }
  return rows;
}

std::string number(double v, const char* format = "%.4g") {
  if (!std::isfinite(v)) return "–";
  char text[40];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

// One matrix as a small borderless table, one row per output (cells already HTML).
std::string matrix_table(const std::vector<std::vector<std::string>>& rows) {
  std::string text = "<table class=\"m\">";
  for (const auto& row : rows) {
    text += "<tr>";
    for (const std::string& cell : row) text += "<td>" + cell + "</td>";
    text += "</tr>";
  }
  return text + "</table>";
}

// G(0), each element ± its standard error when `with_se`; "–" where not estimated.
std::string matrix_text(const IdentifiedModel& m, bool with_se) {
  std::vector<std::vector<std::string>> rows(static_cast<std::size_t>(m.outputs));
  for (int o = 0; o < m.outputs; ++o) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      std::string cell = e.estimated() ? number(e.value.static_gain()) : std::string("–");
      if (with_se && e.estimated()) cell += " ± " + number(e.std_error.gain, "%.2g");
      rows[static_cast<std::size_t>(o)].push_back(cell);
    }
  }
  return matrix_table(rows);
}

// The open-loop campaign's model of the same design (its folder beside the open-loop report,
// models/NN-name.json): G(0) as rows and each output's fit; "" when there is none.
std::string open_loop_cell(const fs::path& dir, const std::string& report,
                           const std::string& model) {
  if (report.empty()) return "";
  std::ifstream in(dir / fs::path(report).parent_path() / model);
  if (!in) return "(no open-loop run of this design)";
  const nlohmann::json m = nlohmann::json::parse(in, nullptr, false);
  if (m.is_discarded() || !m.contains("gain")) return "(unreadable)";
  std::vector<std::vector<std::string>> rows;
  for (const auto& row : m["gain"]) {
    rows.emplace_back();
    for (const auto& g : row) rows.back().push_back(g.is_number() ? number(g.get<double>()) : "–");
  }
  std::string fits;
  for (const auto& o : m["outputs"])
    if (o.contains("fit") && o["fit"].is_number())
      fits += (fits.empty() ? "" : " ") + number(o["fit"].get<double>(), "%.1f");
  return matrix_table(rows) + "fit % " + fits;
}

nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json finite_or_null(const Eigen::VectorXd& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const double x : v) a.push_back(finite_or_null(x));
  return a;
}

nlohmann::json balance_json(const Balance& b) {
  return {{"ratio", finite_or_null(b.ratio)},
          {"projection_std", finite_or_null(b.projection_std)},
          {"upsilon", finite_or_null(b.upsilon)}};
}

// The runs named as in the open-loop summary; null where NaN.
nlohmann::json cross_json(const CrossFitFigures& f, const std::vector<ClosedLoopExperiment>& runs) {
  const auto on = [&](Eigen::Index i) {
    return i >= 0 ? nlohmann::json(runs[static_cast<std::size_t>(i)].name)
                  : nlohmann::json(nullptr);
  };
  return {{"average", finite_or_null(f.average)},
          {"best", finite_or_null(f.best)},
          {"worst", finite_or_null(f.worst)},
          {"worst_on", on(f.worst_on)},
          {"loss_average", finite_or_null(f.loss_average)},
          {"loss_worst", finite_or_null(f.loss_worst)},
          {"loss_worst_on", on(f.loss_worst_on)}};
}

// "79.3 (worst 71.0 on prbsUnc), loss 0.4": the cross-validation of one model in words.
std::string cross_text(const ClosedLoopExperiment& e,
                       const std::vector<ClosedLoopExperiment>& runs) {
  if (!std::isfinite(e.cross.average)) return "—";
  std::string text = number(e.cross.average, "%.1f") + " (worst " + number(e.cross.worst, "%.1f") +
                     " on " + runs[static_cast<std::size_t>(e.cross.worst_on)].name + ")";
  if (std::isfinite(e.cross.loss_average)) text += ", loss " + number(e.cross.loss_average, "%.1f");
  return text;
}

// Where the designs' (4.2.3) τ_L came from, one sentence.
std::string pace_text(const ClosedLoopCampaignHeader& h) {
  if (!h.loop_speed)
    return "The designs switch at the plant's pace: τ_L = " + number(h.tau_low_min, "%.0f") +
           " min, as open loop.";
  return "The designs switch at the loop's pace: the controller, on its own model, follows a "
         "switch of r along the prior's weakest output direction in " +
         std::string(h.loop_speed->reached ? "" : "more than ") +
         number(h.loop_speed->time_constant_min, "%.0f") +
         " min (63 %), and τ_L = " + number(h.tau_low_min, "%.0f") + " min by (4.2.3).";
}

}  // namespace

void write_closed_loop_summary(const ClosedLoopCampaignHeader& h,
                               const std::vector<ClosedLoopExperiment>& runs, const fs::path& dir) {
  nlohmann::json j;
  j["format"] = "excite closed-loop campaign v1";
  j["plant"] = h.plant;
  j["controller"] = fs::path(h.controller).filename().string();
  j["excitation"] = h.excitation;
  j["directions"] = h.directions;
  j["through_the_gateway"] = h.loop;
  if (h.excitation == "setpoint") j["switching"] = h.switching;
  j["tau_low_min"] = h.tau_low_min;
  if (h.loop_speed) {
    j["loop_time_constant_min"] = h.loop_speed->time_constant_min;
    j["loop_time_constant_reached"] = h.loop_speed->reached;
  }
  j["experiments"] = nlohmann::json::array();
  for (const ClosedLoopExperiment& e : runs) {
    const IdentificationResult& two = e.identified.two_stage;
    std::vector<double> fits, explained;
    for (const OutputFit& f : two.fits) fits.push_back(f.fit_percent);
    for (Eigen::Index i = 0; i < e.identified.stage1.fit_percent.size(); ++i)
      explained.push_back(e.identified.stage1.fit_percent(i));
    j["experiments"].push_back({{"number", e.number},
                                {"name", e.name},
                                {"rows", e.rows},
                                {"rows_mv_limited", e.rows_mv_limited},
                                {"run_log", e.run_log},
                                {"model", e.model},
                                {"fit_percent", fits},
                                {"gain", gain_rows(two.model, false)},
                                {"gain_std_error", gain_rows(two.model, true)},
                                {"direct_gain", gain_rows(e.identified.direct.model, false)},
                                {"u_explained_by_r_percent", explained},
                                {"feedback_bias_suspected", e.identified.feedback_bias.size()},
                                {"balance", balance_json(e.balance)},
                                {"truth_fit_percent", finite_or_null(e.truth_fit)},
                                {"crossfit_percent", finite_or_null(e.crossfit)},
                                {"crossfit", cross_json(e.cross, runs)}});
  }
  write_whole_file(dir / "summary.json", j.dump(2) + "\n");
}

void write_closed_loop_report(const ClosedLoopCampaignHeader& h,
                              const std::vector<ClosedLoopExperiment>& runs, const fs::path& dir) {
  const Eigen::MatrixXd g0 = sim::make_plant(h.plant)->static_gain();
  std::ostringstream s;
  const auto esc = [](const std::string& t) { return html_escaped(t); };
  s << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" << esc(h.plant)
    << " with the controller on</title>\n<style>body{font-family:sans-serif;max-width:70em;"
       "margin:1em auto}table{border-collapse:collapse}td,th{border:1px solid #ccc;"
       "padding:.3em .6em;vertical-align:top;text-align:right}td{white-space:nowrap}"
       ".m td{border:none;padding:0 .4em}.m{margin-bottom:.4em}"
       "</style></head><body>\n";
  s << "<h1>" << esc(h.plant) << ": the closed-loop designs</h1>\n<p>Controller "
    << esc(fs::path(h.controller).filename().string()) << ", " << esc(h.excitation) << " excitation"
    << (h.directions == "output" ? " along the prior's output directions" : "") << ", "
    << (h.loop ? "every run streamed through the real excite-gateway to excite-plant "
                 "--controller (lock-step; the gateway's run-log v4)"
               : "every run simulated in process (excite simulate --controller)")
    << ". " << pace_text(h)
    << " Identified by the two-stage method (stage 1: the part of u that r explains; stage "
       "2: the per-element structures on it); the direct fit on the applied u beside it.";
  if (!h.open_loop_report.empty()) {
    s << " The open-loop designs of the same plant: <a href=\"" << esc(h.open_loop_report)
      << "\">the open-loop report</a>.";
  }
  s << "</p>\n<p>True G(0):</p>";
  std::vector<std::vector<std::string>> truth(static_cast<std::size_t>(g0.rows()));
  for (Eigen::Index o = 0; o < g0.rows(); ++o) {
    for (Eigen::Index i = 0; i < g0.cols(); ++i)
      truth[static_cast<std::size_t>(o)].push_back(number(g0(o, i)));
  }
  s << matrix_table(truth);
  s << "\n<table><tr><th>#</th><th>design</th><th>rows</th><th>fit % per output</th>"
       "<th>balance ratio (Υ)</th><th>cross-fit %, average over the other runs</th>"
       "<th>G(0), two-stage ± SE</th><th>G(0), direct</th><th>u explained by r, %</th>"
       "<th>feedback bias suspected</th><th>files</th>"
    << (h.open_loop_report.empty() ? "" : "<th>the same design open loop: G(0), fit</th>")
    << "</tr>\n";
  for (const ClosedLoopExperiment& e : runs) {
    std::string fits, explained;
    for (const OutputFit& f : e.identified.two_stage.fits)
      fits += (fits.empty() ? "" : " ") + number(f.fit_percent, "%.1f");
    for (Eigen::Index i = 0; i < e.identified.stage1.fit_percent.size(); ++i)
      explained +=
          (explained.empty() ? "" : " ") + number(e.identified.stage1.fit_percent(i), "%.0f");
    s << "<tr><td>" << e.number << "</td><td>" << esc(e.name) << "</td><td>" << e.rows
      << "</td><td>" << fits << "</td><td>" << number(e.balance.ratio, "%.2f") << " ("
      << number(e.balance.upsilon, "%.2f") << ")</td><td>" << esc(cross_text(e, runs))
      << "</td><td>" << matrix_text(e.identified.two_stage.model, true) << "</td><td>"
      << matrix_text(e.identified.direct.model, false) << "</td><td>" << explained << "</td><td>"
      << e.identified.feedback_bias.size() << " elements</td><td><a href=\"" << esc(e.run_log)
      << "\">run log</a> <a href=\"" << esc(e.model) << "\">model</a></td>";
    if (!h.open_loop_report.empty())
      s << "<td>" << open_loop_cell(dir, h.open_loop_report, e.model) << "</td>";
    s << "</tr>\n";
  }
  s << "</table>\n<p>Balance ratio: the smallest over the largest standard deviation of the "
       "measured outputs projected on the true G(0)'s output directions (5.5.2; 1: every "
       "direction as excited as the strongest); Υ: the determinant of the outputs' "
       "correlation matrix (6.2.1). Cross-fit: each run's two-stage model simulated on every "
       "other run's applied u from rest, fit % averaged over the outputs (SPEC §6); loss: "
       "the true plant's fit on those runs minus the model's, in points.</p>\n";
  const std::vector<std::string> figures = draw_closed_loop_figures(runs, dir, h.threads);
  s << "<h2>The runs</h2>\n";
  for (std::size_t k = 0; k < runs.size(); ++k) {
    s << "<p><img src=\"" << esc(figures[k]) << "\" alt=\"" << esc(runs[k].name)
      << ": the CVs, the MVs and r over time\"></p>\n";
  }
  s << "</body></html>\n";
  write_whole_file(dir / "index.html", s.str());
}

}  // namespace excite::host
