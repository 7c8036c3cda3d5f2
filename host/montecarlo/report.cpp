// SPDX-License-Identifier: MIT
#include "host/montecarlo/report.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "host/campaign/gnuplot.hpp"
#include "host/campaign/report.hpp"
#include "host/campaign/report_figures.hpp"
#include "host/montecarlo/records.hpp"
#include "host/montecarlo/statistics.hpp"
#include "host/output/html_page.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::montecarlo {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kOthersColour = "#e08020";       // the campaign report's colours
constexpr const char* kDirectionalColour = "#3060c0";  // (host/campaign/report_figures.cpp)

// A figure of the per-design distributions: what is plotted per unit, and its references.
struct BoxMetric {
  const char* key;  // metric-KEY.svg; summary.json's "verdicts" key
  const char* title;
  const char* axis;
  double (*value)(const UnitResult&);
  std::vector<std::pair<double, const char*>> references;  // horizontal lines: value, label
};

const std::vector<BoxMetric>& box_metrics() {
  static const std::vector<BoxMetric> metrics = {
      {"fit",
       "own fit (5.5.1), averaged over the outputs",
       "own fit [%]",
       [](const UnitResult& u) { return u.fit_avg; },
       {}},
      {"crossfit_worst",
       "worst cross-fit: the model on the other designs' runs of its seed",
       "worst cross-fit [%]",
       [](const UnitResult& u) { return u.crossfit_worst; },
       {}},
      {"ratio",
       "output balance on the noise-free outputs (5.5.2): min/max projection std",
       "ratio [–] (1 = balanced)",
       [](const UnitResult& u) { return u.ratio; },
       {}},
      {"sigma_n_error_percent",
       "error of the smallest singular value σ_n of the identified G(0)",
       "(σ̂_n − σ_n)/σ_n [%]",
       [](const UnitResult& u) { return 100.0 * u.accuracy.sigma_n_error; },
       {{20.0, "criterion ±20 %"}, {-20.0, ""}}},
      {"weakest_direction_angle_deg",
       "angle between the identified and the true weakest input "
       "direction v_n",
       "∠(v̂_n, ±v_n) [°]",
       [](const UnitResult& u) { return u.accuracy.weakest_angle_deg; },
       {{10.0, "criterion 10°"}}},
  };
  return metrics;
}

std::string fixed(double v, int digits) {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

// The designs as the figures place them: the others first, then the directional ones, each
// group in Table order, one empty slot between the groups. x is 1-based.
struct Placed {
  std::string name;
  bool directional = false;
  double x = 0.0;
};
struct Layout {
  std::vector<Placed> designs;
  double separator = 0.0;  // x of the line between the groups; 0: one group only
  double width = 1.0;      // xrange [0, width]
};

Layout layout_of(const std::vector<std::string>& names) {
  Layout l;
  double x = 0.0;
  for (const bool directional : {false, true}) {
    bool any = false;
    for (const std::string& n : names) {
      if (is_directional_design(n) != directional) continue;
      if (!any && !l.designs.empty()) {
        x += 1.0;
        l.separator = x;
      }
      any = true;
      x += 1.0;
      l.designs.push_back({n, directional, x});
    }
  }
  l.width = x + 1.0;
  return l;
}

std::string xtics(const Layout& l) {
  std::string out = "set xtics rotate by -35 noenhanced (";
  for (std::size_t k = 0; k < l.designs.size(); ++k) {
    out += (k ? ", " : "") + gnuplot_string(l.designs[k].name) + " " +
           std::to_string(static_cast<int>(l.designs[k].x));
  }
  return out + ")\n";
}

std::string separator(const Layout& l) {
  if (l.separator == 0.0) return "";
  std::ostringstream out;
  out << "set arrow from " << l.separator << ", graph 0 to " << l.separator
      << ", graph 1 nohead dt 3 lc rgb 'gray'\n";
  return out.str();
}

std::vector<const UnitResult*> units_of(const std::vector<UnitResult>& units,
                                        const std::string& design) {
  std::vector<const UnitResult*> out;
  for (const UnitResult& u : units) {
    if (u.design == design) out.push_back(&u);
  }
  return out;
}

Spread spread_over(const std::vector<const UnitResult*>& units,
                   double (*value)(const UnitResult&)) {
  std::vector<double> v;
  for (const UnitResult* u : units) v.push_back(value(*u));
  return spread_of(v);
}

// metric-KEY.svg: per design a box from the lower to the upper quartile, whiskers over the
// 10–90 % range and the median as a thick line; the others orange, directional blue. Returns
// the script's name, or "" when no design has a finite value (no figure).
std::string plot_metric(const BoxMetric& m, const Layout& l, const std::vector<UnitResult>& units,
                        const fs::path& figures) {
  std::ostringstream data[2];
  bool any[2] = {false, false};
  for (const Placed& p : l.designs) {
    const Spread s = spread_over(units_of(units, p.name), m.value);
    if (s.finite == 0) continue;
    const int g = p.directional ? 1 : 0;
    char row[256];
    std::snprintf(row, sizeof row, "%g %.10g %.10g %.10g %.10g %.10g\n", p.x, s.p10, s.p25,
                  s.median, s.p75, s.p90);
    data[g] << row;
    any[g] = true;
  }
  if (!any[0] && !any[1]) return "";
  const std::string key = m.key;
  const std::string file = source_name("metric-" + key + ".dat");
  write_figure_source(figures, file, data[0].str() + "\n\n" + data[1].str());
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 1000,330 dynamic font 'sans,10'\nset output "
     << gnuplot_string("metric-" + key + ".svg") << "\nset title "
     << gnuplot_string(std::string(m.title) +
                       ": box quartiles, whiskers 10–90 %, line median over the seeds")
     << " noenhanced\nset ylabel " << gnuplot_string(m.axis)
     << " noenhanced\nset grid ytics\nset key outside right top noenhanced\n"
        "set style fill solid 0.35 border\nset boxwidth 0.6\nset xrange [0:"
     << l.width << "]\n"
     << xtics(l) << separator(l) << "plot";
  const char* colours[2] = {kOthersColour, kDirectionalColour};
  const char* titles[2] = {"other designs", "directional designs"};
  bool first = true;
  for (int g = 0; g < 2; ++g) {
    if (!any[g]) continue;
    gp << (first ? " " : ", ") << gnuplot_string(file) << " index " << g
       << " using 1:3:2:6:5 with candlesticks whiskerbars lc rgb '" << colours[g] << "' title "
       << gnuplot_string(titles[g]) << ", " << gnuplot_string(file) << " index " << g
       << " using 1:4:4:4:4 with candlesticks lw 3 lc rgb '" << colours[g] << "' notitle";
    first = false;
  }
  for (const auto& [value, label] : m.references) {
    gp << ", " << value << " with lines dt 2 lc rgb 'black' "
       << (*label ? "title " + gnuplot_string(label) : std::string("notitle"));
  }
  gp << '\n';
  const std::string script = source_name("metric-" + key + ".gp");
  write_figure_source(figures, script, gp.str());
  return script;
}

// t90.svg: T90 per design in percent of the run, a bar each; "none" where no length reaches
// 90 % from then on.
std::string plot_t90(const json& summary, const Layout& l, const fs::path& figures) {
  std::ostringstream bars[2], labels;
  bool any[2] = {false, false};
  for (const Placed& p : l.designs) {
    const json* d = nullptr;
    for (const json& x : summary["designs"]) {
      if (x["design"] == p.name) d = &x;
    }
    if (d == nullptr) continue;
    const json& t90 = (*d)["t90"];
    char row[128];
    if (t90.is_null()) {
      std::snprintf(row, sizeof row, "%g 2 \"none\"\n", p.x);
      labels << row;
      continue;
    }
    const int g = p.directional ? 1 : 0;
    std::snprintf(row, sizeof row, "%g %d\n", p.x, t90["percent"].get<int>());
    bars[g] << row;
    any[g] = true;
    std::snprintf(row, sizeof row, "%g %d \"%.0f min\"\n", p.x, t90["percent"].get<int>(),
                  t90["minutes"].get<double>());
    labels << row;
  }
  const std::string file = source_name("t90.dat");
  std::string text = bars[0].str() + "\n\n" + bars[1].str() + "\n\n" + labels.str();
  write_figure_source(figures, file, text);
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 1000,330 dynamic font 'sans,10'\nset output "
     << gnuplot_string("t90.svg") << "\nset title "
     << gnuplot_string(
            "T90: the shortest test length from which on ≥ 90 % of the seeds meet the criterion "
            "(label: minutes)")
     << " noenhanced\nset ylabel 'T90 [% of the run]'\nset yrange [0:115]\nset grid ytics\n"
        "set key outside right top noenhanced\nset style fill solid 0.6 border\nset boxwidth "
        "0.6\nset xrange [0:"
     << l.width << "]\n"
     << xtics(l) << separator(l) << "plot";
  const char* colours[2] = {kOthersColour, kDirectionalColour};
  const char* titles[2] = {"other designs", "directional designs"};
  bool first = true;
  for (int g = 0; g < 2; ++g) {
    if (!any[g]) continue;
    gp << (first ? " " : ", ") << gnuplot_string(file) << " index " << g
       << " using 1:2 with boxes lc rgb '" << colours[g] << "' title " << gnuplot_string(titles[g]);
    first = false;
  }
  gp << (first ? " " : ", ") << gnuplot_string(file)
     << " index 2 using 1:2:3 with labels offset 0,0.8 font 'sans,8' notitle\n";
  const std::string script = source_name("t90.gp");
  write_figure_source(figures, script, gp.str());
  return script;
}

// shares.svg: per design (small multiples) the share of seeds meeting the criterion against
// the test length, with its Wilson 95 % band, the 90 % line and T90 marked.
std::string plot_shares(const json& summary, const Layout& l, const fs::path& figures) {
  std::ostringstream data;
  std::vector<const json*> order;
  for (const Placed& p : l.designs) {
    for (const json& d : summary["designs"]) {
      if (d["design"] == p.name) order.push_back(&d);
    }
  }
  for (const json* d : order) {
    for (const json& point : (*d)["lengths"]) {
      char row[128];
      std::snprintf(row, sizeof row, "%d %.10g %.10g %.10g\n", point["percent"].get<int>(),
                    number_of(point["share"]), point["wilson95"][0].get<double>(),
                    point["wilson95"][1].get<double>());
      data << row;
    }
    data << "\n\n";
  }
  const std::string file = source_name("shares.dat");
  write_figure_source(figures, file, data.str());
  const auto rows = static_cast<int>((order.size() + 3) / 4);
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 1150," << 210 * rows + 60
     << " dynamic font 'sans,9'\nset output " << gnuplot_string("shares.svg")
     << "\nset multiplot layout " << rows << ",4 title "
     << gnuplot_string(
            "share of seeds meeting the criterion against the test length, Wilson 95 % band; "
            "dashed: 90 %, dotted: T90")
     << " noenhanced\nunset key\nset grid\nset xrange [0:100]\nset yrange [0:1.05]\n"
        "set xlabel 'test length [% of the run]'\nset ylabel 'share of seeds'\n"
        "set style fill transparent solid 0.25 noborder\n";
  for (std::size_t k = 0; k < order.size(); ++k) {
    const json& d = *order[k];
    const std::string name = d["design"].get<std::string>();
    const char* colour = is_directional_design(name) ? kDirectionalColour : kOthersColour;
    const json& t90 = d["t90"];
    gp << "set title "
       << gnuplot_string(name + ": T90 " +
                         (t90.is_null() ? std::string("none")
                                        : std::to_string(t90["percent"].get<int>()) + " %"))
       << " noenhanced\nunset arrow\n";
    if (!t90.is_null()) {
      gp << "set arrow from " << t90["percent"].get<int>() << ", graph 0 to "
         << t90["percent"].get<int>() << ", graph 1 nohead dt 3 lc rgb 'black'\n";
    }
    gp << "plot " << gnuplot_string(file) << " index " << k
       << " using 1:3:4 with filledcurves lc rgb '" << colour << "', " << gnuplot_string(file)
       << " index " << k << " using 1:2 with linespoints pt 7 ps 0.4 lw 1.5 lc rgb '" << colour
       << "', 0.9 with lines dt 2 lc rgb 'black'\n";
  }
  gp << "unset multiplot\n";
  const std::string script = source_name("shares.gp");
  write_figure_source(figures, script, gp.str());
  return script;
}

std::string share_text(const json& s) {
  char text[96];
  std::snprintf(text, sizeof text, "%d of %d [%.2f–%.2f]", s["met"].get<int>(), s["of"].get<int>(),
                s["wilson95"][0].get<double>(), s["wilson95"][1].get<double>());
  return text;
}

// A spread's cell: the median bold, then [p10 – p90].
struct SpreadCell {
  const json& spread;
  int digits;
};
HtmlPage& operator<<(HtmlPage& h, const SpreadCell& c) {
  return h << "<b>" << fixed(number_of(c.spread["median"]), c.digits) << "</b> ["
           << fixed(number_of(c.spread["p10"]), c.digits) << " – "
           << fixed(number_of(c.spread["p90"]), c.digits) << "]";
}

// A table row's class: shaded for a directional design.
Markup row_class(bool directional) {
  return directional ? Markup(" class='dir'") : Markup("");
}

// The figures (gnuplot scripts this run wrote, drawn as SVGs); returns the metrics that
// have one.
std::vector<std::string> draw_figures(const json& summary, const Layout& layout,
                                      const std::vector<UnitResult>& units, const fs::path& dir,
                                      int threads) {
  const fs::path figures = dir / "figures";
  fs::create_directories(figures);
  make_figure_sources(figures);
  std::vector<std::string> scripts;
  std::vector<std::string> drawn_metrics;  // keys with a figure
  for (const BoxMetric& m : box_metrics()) {
    const std::string script = plot_metric(m, layout, units, figures);
    if (script.empty()) continue;
    scripts.push_back(script);
    drawn_metrics.emplace_back(m.key);
  }
  scripts.push_back(plot_t90(summary, layout, figures));
  scripts.push_back(plot_shares(summary, layout, figures));
  run_gnuplot_scripts(figures, scripts, threads);
  remove_figure_sources(figures);
  return drawn_metrics;
}

// Title, what was run, the true plant, the criterion, T90 and how spreads are given.
void head_section(HtmlPage& h, const json& summary, std::size_t designs) {
  const json& run = summary["run"];
  const std::string plant = run["plant"].get<std::string>();
  const int seeds = run["seeds"].get<int>();
  const auto first_seed = run["first_seed"].get<std::uint64_t>();
  const double perturb = run.value("perturb_percent", 0.0);
  h << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>excite montecarlo: "
    << plant << "</title><style>" << CodeMarkup{report_style()}
    << "table.spreads td{white-space:nowrap}</style></head><body>";
  h << "<h1>Monte Carlo: " << plant << ", " << seeds << " seeds</h1>";
  h << "<p>The campaign's experiment (design → simulate → identify → cross-validate → balance) "
       "for "
    << designs << " designs over " << seeds << " noise seeds (" << first_seed << " to "
    << first_seed + static_cast<std::uint64_t>(seeds) - 1 << "), measurement noise variance "
    << number_of(run["noise_variance"]) << " on every output. Rows of directional designs are "
    << "shaded; in the figures the other designs are orange and the directional ones blue.</p>";
  h << "<p><b>True plant: "
    << (perturb > 0.0 ? Markup("perturbed</b> in every seed: ") : Markup("nominal</b>: "))
    << run["true_plant"].get<std::string>() << ".</p>";
  if (run.contains("closed_loop"))
    h << "<p><b>Controller on:</b> " << run["closed_loop"]["text"].get<std::string>() << ".</p>";
  for (const json& d : summary["designs"]) {
    if (!d.contains("cv_limits")) continue;
    const json& l = d["cv_limits"];
    h << "<p><b>" << d["design"].get<std::string>() << ", CV test limits:</b> "
      << l["seeds_outside"].get<int>() << " of " << l["of"].get<int>()
      << " seeds outside them; peak |CV| / limit, median " << number_of(l["peak_ratio"]["median"])
      << ", largest " << number_of(l["largest_peak_ratio"]) << ".</p>";
  }
  for (const json& d : summary["designs"]) {
    if (!d.contains("not_run")) continue;
    h << "<p><b>" << d["design"].get<std::string>() << ": " << d["not_run"]["seeds"].get<int>()
      << " seeds not run</b>, not in its shares or T90 (first: "
      << d["not_run"]["first"].get<std::string>() << ").</p>";
  }
  h << "<p><b>Accuracy criterion:</b> " << summary["criterion"]["text"].get<std::string>()
    << ". <b>T90:</b> " << summary["t90_definition"].get<std::string>()
    << ". Spreads: " << summary["spread"].get<std::string>() << "; shares with the "
    << summary["intervals"].get<std::string>()
    << ". Numbers: <a href='summary.json'>summary.json</a>.</p>";
}

// The verdicts: directional designs against the others, with the seeds they hold in.
void verdicts_section(HtmlPage& h, const json& summary) {
  h << "<h2>Directional designs against the others</h2><p class='note'>"
    << summary["verdict_definition"].get<std::string>()
    << ". Shares with the Wilson 95 % interval.</p><table><tr><th>metric</th><th>better</th>"
       "<th>directional median</th><th>others' median</th><th>verdict (by median)</th><th>holds "
       "in (seeds)</th><th>best directional beats best other in (seeds)</th></tr>";
  for (const json& v : summary["verdicts"]) {
    h << "<tr><td>" << v["label"].get<std::string>() << "</td><td>"
      << v["better"].get<std::string>() << "</td><td>"
      << fixed(number_of(v["directional_median"]), 3) << "</td><td>"
      << fixed(number_of(v["others_median"]), 3) << "</td>";
    if (v["verdict"].is_null()) {
      h << "<td colspan='3'>– (needs designs of both groups)</td></tr>";
      continue;
    }
    const json& holds = v["holds_in_seeds"];
    const std::string verdict = v["verdict"].get<std::string>();
    if (verdict == "directional not better") {
      h << "<td>directional <b>not</b> better";
    } else {
      h << "<td>" << verdict;
    }
    h << " in " << holds["met"].get<int>() << " of " << holds["of"].get<int>() << " seeds</td><td>"
      << share_text(holds) << "</td><td>" << share_text(v["best_directional_better_in_seeds"])
      << "</td></tr>";
  }
  h << "</table>";
}

// Each metric's distribution over the seeds (a figure, or why there is none).
void distributions_section(HtmlPage& h, const std::vector<std::string>& drawn_metrics) {
  h << "<h2>Distributions over the seeds, per design</h2>";
  for (const BoxMetric& m : box_metrics()) {
    bool drawn = false;
    for (const std::string& k : drawn_metrics) drawn = drawn || k == m.key;
    if (!drawn) {
      h << "<p class='note'>" << std::string(m.title) << ": no design has a value"
        << (std::string(m.key) == "crossfit_worst" ? Markup(" (one design: no other runs to fit)")
                                                   : Markup(""))
        << ".</p>";
      continue;
    }
    h << "<img src='figures/metric-" << std::string(m.key) << ".svg' alt='" << std::string(m.key)
      << " per design'>";
  }
}

// Test length: the criterion's share over the whole run and T90, per design.
void length_section(HtmlPage& h, const json& summary, const Layout& layout) {
  h << "<h2>Test length</h2><img src='figures/t90.svg' alt='T90 per design'>"
       "<table><tr><th>design</th><th>group</th><th>samples</th><th>criterion met, whole run "
       "[Wilson 95 %]</th><th>T90 [% of the run]</th><th>T90 [min]</th></tr>";
  for (const Placed& p : layout.designs) {
    for (const json& d : summary["designs"]) {
      if (d["design"] != p.name) continue;
      const json& t90 = d["t90"];
      h << "<tr" << row_class(p.directional) << "><td>" << d["number"].get<int>() << ' ' << p.name
        << "</td><td>" << std::string(p.directional ? "directional" : "other") << "</td><td>"
        << d["samples"].get<long long>() << "</td><td>" << share_text(d["criterion"]) << "</td><td>"
        << (t90.is_null() ? std::string("none") : std::to_string(t90["percent"].get<int>()))
        << "</td><td>" << (t90.is_null() ? std::string("–") : fixed(number_of(t90["minutes"]), 0))
        << "</td></tr>";
    }
  }
  h << "</table><img src='figures/shares.svg' alt='share of seeds against the test length'>";
}

// Spreads of the headline figures per design.
void spreads_section(HtmlPage& h, const json& summary, const Layout& layout) {
  h << "<h2>Spreads per design</h2><p class='note'>Median <b>bold</b> and [10 % – 90 %] over the "
       "seeds.</p><table class='spreads'><tr><th>design</th><th>own fit [%]</th><th>worst "
       "cross-fit [%]</th>"
       "<th>ratio, noise-free [–]</th><th>Υ, noise-free [–]</th><th>σ_n error [%]</th>"
       "<th>v_n angle [°]</th></tr>";
  for (const Placed& p : layout.designs) {
    for (const json& d : summary["designs"]) {
      if (d["design"] != p.name) continue;
      h << "<tr" << row_class(p.directional) << "><td>" << p.name << "</td><td>"
        << SpreadCell{d["fit"], 1} << "</td><td>" << SpreadCell{d["crossfit_worst"], 1}
        << "</td><td>" << SpreadCell{d["ratio"], 3} << "</td><td>" << SpreadCell{d["upsilon"], 3}
        << "</td><td>" << SpreadCell{d["sigma_n_error_percent"], 1} << "</td><td>"
        << SpreadCell{d["weakest_direction_angle_deg"], 1} << "</td></tr>";
    }
  }
  h << "</table>";
}

// Elements of G(0) whose bias exceeds their spread, per design; closes the page.
void bias_section(HtmlPage& h, const json& summary, const Layout& layout) {
  const double perturb = summary["run"].value("perturb_percent", 0.0);
  h << "<h2>Bias against spread, per element of G(0)</h2><p class='note'>"
    << summary["bias_definition"].get<std::string>()
    << ". Listed: the elements so flagged (true gain "
    << (perturb > 0.0 ? Markup("nominal; ") : Markup(""))
    << "median identified, median error and the error's 10–90 % range).</p><table><tr><th>"
       "design</th><th>elements biased beyond their spread</th></tr>";
  for (const Placed& p : layout.designs) {
    for (const json& d : summary["designs"]) {
      if (d["design"] != p.name) continue;
      std::string biased;
      for (const json& e : d["gain_elements"]) {
        if (!e["bias_exceeds_spread"].get<bool>()) continue;
        char text[160];
        std::snprintf(text, sizeof text, "g%d%d %.3g (true %.3g, error %+.3g, range %.3g)",
                      e["output"].get<int>() + 1, e["input"].get<int>() + 1, number_of(e["median"]),
                      number_of(e["true"]), number_of(e["error"]["median"]),
                      number_of(e["error"]["p90"]) - number_of(e["error"]["p10"]));
        biased += (biased.empty() ? "" : "; ") + std::string(text);
      }
      h << "<tr" << row_class(p.directional) << "><td>" << p.name
        << "</td><td style='text-align:left'>" << (biased.empty() ? "none" : biased)
        << "</td></tr>";
    }
  }
  h << "</table></body></html>\n";
}

}  // namespace

void write_report(const json& summary, const std::vector<UnitResult>& units, const fs::path& dir,
                  int threads) {
  std::vector<std::string> names;
  for (const json& d : summary["run"]["designs"]) names.push_back(d.get<std::string>());
  const Layout layout = layout_of(names);
  const std::vector<std::string> drawn_metrics = draw_figures(summary, layout, units, dir, threads);
  HtmlPage h;
  head_section(h, summary, names.size());
  verdicts_section(h, summary);
  distributions_section(h, drawn_metrics);
  length_section(h, summary, layout);
  spreads_section(h, summary, layout);
  bias_section(h, summary, layout);
  write_whole_file(dir / "index.html", h.str());
}

}  // namespace excite::host::montecarlo
