// SPDX-License-Identifier: MIT
#include "host/campaign/report.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>
#include <vector>

#include "host/campaign/gnuplot.hpp"
#include "host/campaign/model_views.hpp"
#include "host/campaign/report_figures.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/parallel.hpp"

namespace excite::host {
namespace {

nlohmann::json number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

nlohmann::json vector(const Eigen::VectorXd& v) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index i = 0; i < v.size(); ++i) out.push_back(number(v(i)));
  return out;
}

std::string fixed(double v, int digits = 3) {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, v);
  return buffer;
}

std::string general(double v) {
  if (!std::isfinite(v)) return "–";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.4g", v);
  return buffer;
}

bool directional(const std::string& name) {
  return is_directional_design(name);
}

// "auto" or the structure forced on every element (summary.json's "structure").
std::string structure_name(const CampaignResult& r) {
  return r.structure ? to_string(*r.structure) : "auto";
}

// How many elements of all the campaign's models ended in each structure, most first:
// "two_poles 180, first_order 52, …" (elements without an estimate not counted).
std::string structures_used(const CampaignResult& r) {
  std::vector<std::pair<int, std::string>> counts;
  for (int k = 0; k < kStructures; ++k) {
    int count = 0;
    for (const Experiment& e : r.experiments) {
      for (const ElementEstimate& el : e.identified.model.elements)
        count += el.estimated() && el.value.structure == static_cast<Structure>(k);
    }
    if (count > 0) counts.emplace_back(count, to_string(static_cast<Structure>(k)));
  }
  std::stable_sort(counts.begin(), counts.end(),
                   [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out;
  for (const auto& [count, name] : counts)
    out += (out.empty() ? "" : ", ") + name + " " + std::to_string(count);
  return out.empty() ? "none" : out;
}

// What was fitted (issue 45): the structure per element, beside the thesis's class.
std::string model_class_text(const CampaignResult& r) {
  if (r.structure) {
    return "every element of every model in one structure, <b>" + structure_name(r) + "</b>" +
           (*r.structure == Structure::two_poles
                ? " (two poles and a delay, 6.1.1): the thesis's model class, in which its "
                  "Tables 6.3–6.5 were drawn"
                : " (forced by --structure; the thesis fitted two poles and a delay, 6.1.1)");
  }
  return "each element of a model in the structure its data support, chosen by BIC among "
         "first order, two poles, two poles with a zero, integrator and underdamped (with or "
         "without a lag and a zero; host/identify/README.md) — here " +
         structures_used(r) +
         " elements — where the thesis fitted two poles and a delay (6.1.1) to every element "
         "(<code>--structure two_poles</code> runs the campaign in its class)";
}

// The name of experiment `k` of the campaign, "–" for -1.
std::string run_name(const CampaignResult& r, int k) {
  return k >= 0 && static_cast<std::size_t>(k) < r.experiments.size()
             ? r.experiments[static_cast<std::size_t>(k)].name
             : std::string("–");
}

nlohmann::json run_name_json(const CampaignResult& r, int k) {
  return k >= 0 ? nlohmann::json(run_name(r, k)) : nlohmann::json(nullptr);
}

// Each input's crest factor over its active span (first to last non-zero sample: its slot,
// or the whole experiment), as the 'CF period' average is taken (host/measures), "–" for an
// input that does not move.
std::string per_input_crest_factors(const Eigen::MatrixXd& U) {
  std::string out;
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    Eigen::Index first = 0, last = U.rows() - 1;
    while (first < U.rows() && U(first, j) == 0.0) ++first;
    while (last > first && U(last, j) == 0.0) --last;
    std::string cf = "–";
    if (first < U.rows()) {
      const auto span = U.col(j).segment(first, last - first + 1);
      const double rms = std::sqrt(span.squaredNorm() / static_cast<double>(span.size()));
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%.3f", span.cwiseAbs().maxCoeff() / rms);
      cf = buffer;
    }
    out += (j ? " " : "") + cf;
  }
  return out;
}

// A figure inside a collapsed model section: loaded only when the section is opened (issue
// 23 §3: a browser parses every SVG <img> of a page when it loads, even in a closed
// <details>, and the 51 model views made the page take seconds to open); without
// JavaScript the <noscript> copy loads as before.
std::string deferred_image(const std::string& src, const std::string& alt) {
  return "<img data-src='" + src + "' alt='" + alt + "'><noscript><img src='" + src + "' alt='" +
         alt + "'></noscript>";
}

// A metric over one group of designs (directional or not): every statistic, so that no
// single average decides (an outlier moves the mean, not the median).
struct GroupStats {
  double median = std::nan(""), mean = std::nan(""), min = std::nan(""), max = std::nan("");
  int count = 0, missing = 0;
};

template <typename Field>
GroupStats stats_over(const CampaignResult& r, bool dir, Field field) {
  std::vector<double> v;
  GroupStats g;
  for (const Experiment& e : r.experiments) {
    if (directional(e.name) != dir) continue;
    const double x = field(e);
    if (std::isfinite(x)) {
      v.push_back(x);
    } else {
      ++g.missing;
    }
  }
  g.count = static_cast<int>(v.size());
  if (v.empty()) return g;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  g.median = v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
  double sum = 0.0;
  for (const double x : v) sum += x;
  g.mean = sum / static_cast<double>(v.size());
  g.min = v.front();
  g.max = v.back();
  return g;
}

// The conventions a reader needs to compare the figures with the thesis's (SPEC §3, §4).
std::vector<std::string> convention_lines(const CampaignResult& r) {
  std::vector<std::string> lines;
  lines.push_back(
      r.sized_by_static_output
          ? "Amplitudes: every design sized by the static output it causes (SPEC §3): plain "
            "designs move input j by c/‖G(0)e_j‖, directional designs along c·σ_i⁻¹v_i, with the "
            "thesis's factor c per design (host/design/sizing.cpp; peak for steps and PRBS, RMS "
            "for multisines). Input limits are separate; a design that does not fit is scaled "
            "as a whole (column 'limit scale')."
          : "Amplitudes: this plant's designs are sized by input amplitude (its case study, "
            "host/design/case_studies.cpp); directional designs match the static output RMS of "
            "their plain counterparts.");
  lines.push_back("Noise: Gaussian, variance " + general(r.noise_variance) +
                  " on every output (--noise-var overrides). " +
                  (r.sized_by_static_output
                       ? "The linear case studies' default 5·10⁻⁴ is the thesis's s² = 0.03 read "
                         "as a Simulink noise power over its 60 s sample time (0.03/60, SPEC §4)."
                       : "The columns' default 10⁻⁸ is a composition analyser's 10⁻⁴ mole "
                         "fraction, in the outputs' own unit."));
  lines.push_back("Gain used for the designs: " + r.design_gain_source +
                  " (--design-gain step-test designs from the step test's estimate).");
  lines.push_back(
      "Balance: projections on the true output directions w_i (5.5.2) and Υ (6.2.1) are "
      "properties of the excitation and are measured on the noise-free simulated outputs; the "
      "figures on the noisy outputs stand beside them, labelled.");
  lines.push_back(
      "Crest factors: 'CF period' over each input's active span (first to last non-zero "
      "sample: its slot in a sequential design, else the whole experiment), per input and "
      "averaged; 'CF experiment' over the whole experiment. Every design lasts the same "
      "number of samples (SPEC §4); a sequential multisine plays each channel alone in one of "
      "n slots, its periodic signal continued through the slot, so its experiment CF is about "
      "√n times its slot's");
  return lines;
}

nlohmann::json conventions(const CampaignResult& r) {
  return {{"noise_variance", r.noise_variance},
          {"sizing", r.sized_by_static_output ? "static_output" : "input_amplitude"},
          {"design_gain", r.design_gain_source},
          {"balance_measured_on", "noise-free outputs (ratio, upsilon); noisy beside (*_noisy)"},
          {"text", convention_lines(r)}};
}

// The report's figures: the gnuplot scripts this run wrote (only these are run), drawn as
// SVGs; returns the step responses' horizon and sample time the quality section states.
struct StepHorizon {
  int samples = 0;
  double sample_time_min = 1.0;
};
StepHorizon draw_figures(const CampaignResult& r, const sim::Plant& plant,
                         const std::filesystem::path& dir, int threads) {
  const auto figures = dir / "figures";
  std::filesystem::create_directories(figures);
  make_figure_sources(figures);
  std::vector<std::string> scripts = write_report_figure_scripts(r, plant, figures, threads);
  const int horizon = report_step_horizon(r);
  const double T = r.experiments.empty() ? 1.0 : r.experiments.front().sample_time_min;
  const Eigen::MatrixXd truth = true_unit_steps(*sim::make_plant(r.plant), horizon, T);
  std::vector<std::vector<std::string>> views(r.experiments.size());
  parallel_for(static_cast<int>(r.experiments.size()), threads, [&](int k) {
    views[static_cast<std::size_t>(k)] = write_model_view_scripts(
        r.experiments[static_cast<std::size_t>(k)], r, truth, horizon, figures);
  });
  for (const auto& v : views) scripts.insert(scripts.end(), v.begin(), v.end());
  run_gnuplot_scripts(figures, scripts, threads);
  remove_figure_sources(figures);  // the report links the SVGs only
  return {horizon, T};
}

// A link to an experiment's file, "–" where there is none.
std::string link_to(const std::vector<std::string>& paths, std::size_t k, const char* text) {
  return k < paths.size() && !paths[k].empty()
             ? "<a href='" + paths[k] + "'>" + std::string(text) + "</a>"
             : std::string("–");
}

// Title, what the study is, the true and design singular values, the conventions.
void head_section(std::ostream& h, const CampaignResult& r, const std::string& out_unit,
                  const std::string& in_unit) {
  h << "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'><title>excite campaign: "
    << r.plant << "</title><style>" << report_style() << "</style></head><body>";
  h << "<h1>Identification campaign: " << r.plant << "</h1>";
  h << "<p>The study of thesis chapter 6 on <b>" << r.plant
    << "</b>: every design of Table 6.1 simulated with measurement noise, a model identified "
       "per output with "
    << model_class_text(r)
    << ", and every model validated on every other experiment. Directional designs used the "
       "gain directions of the <b>"
    << r.design_gain_source << "</b>. Rows of directional designs are shaded.</p>";
  h << "<p>True singular values of G(0) " << gain_unit(out_unit, in_unit) << ":";
  for (Eigen::Index i = 0; i < r.true_gain.singular_values.size(); ++i)
    h << ' ' << general(r.true_gain.singular_values(i));
  h << " (κ = " << general(r.true_gain.condition_number) << "); used for the designs:";
  for (Eigen::Index i = 0; i < r.design_gain.singular_values.size(); ++i) {
    h << ' ' << general(r.design_gain.singular_values(i));
  }
  h << "; the step test's estimate:";
  if (r.step_gain) {
    for (Eigen::Index i = 0; i < r.step_gain->singular_values.size(); ++i)
      h << ' ' << general(r.step_gain->singular_values(i));
  } else {
    h << " none";
  }
  h << ".</p><h2>Conventions</h2><ul>";
  for (const std::string& line : convention_lines(r)) h << "<li>" << line << "</li>";
  h << "</ul>";
}

// What the data show: every metric, median first, for both groups.
void metrics_section(std::ostream& h, const CampaignResult& r) {
  struct Metric {
    const char* name;
    const char* unit;
    bool higher_is_better;
    double (*field)(const Experiment&);
    int digits;
  };
  const Metric metrics[] = {
      {"output balance, noise-free (ratio min/max of the projection std, 1 = balanced)", "–", true,
       [](const Experiment& e) { return e.balance_clean.ratio; }, 3},
      {"Υ = det(corr(Y)), noise-free (1 = uncorrelated outputs)", "–", true,
       [](const Experiment& e) { return e.balance_clean.upsilon; }, 3},
      {"own fit", "%", true, [](const Experiment& e) { return e.fit_avg; }, 1},
      {"cross-fit, average over the other runs", "%", true,
       [](const Experiment& e) { return e.crossfit_avg; }, 1},
      {"cross-fit, worst", "%", true, [](const Experiment& e) { return e.crossfit_worst; }, 1},
      {"loss against the truth, average over the other runs (true plant's fit − cross-fit)",
       "points", false, [](const Experiment& e) { return e.loss_avg; }, 2},
      {"loss against the truth, worst", "points", false,
       [](const Experiment& e) { return e.loss_worst; }, 2},
      {"crest factor over the experiment", "–", false, [](const Experiment& e) { return e.cf_avg; },
       3},
  };
  h << "<h2>What the data show</h2><p class='note'>Each metric over the directional designs "
       "and over the others: median (which one outlier cannot move), mean, range and count. "
       "The verdict compares medians.</p><table><tr><th>metric</th><th>unit</th><th>group</th>"
       "<th>median</th><th>mean</th><th>min</th><th>max</th><th>designs</th><th>verdict (by "
       "median)</th></tr>";
  for (const Metric& m : metrics) {
    const GroupStats directional_stats = stats_over(r, true, m.field);
    const GroupStats other = stats_over(r, false, m.field);
    const bool dir_better = m.higher_is_better ? directional_stats.median > other.median
                                               : directional_stats.median < other.median;
    const std::string verdict =
        !(std::isfinite(directional_stats.median) && std::isfinite(other.median)) ? "–"
        : directional_stats.median == other.median                                ? "equal"
        : dir_better ? "directional better"
                     : "directional <b>not</b> better";
    int row = 0;
    for (const auto& [group, g] :
         {std::pair<const char*, GroupStats>{"directional", directional_stats},
          std::pair<const char*, GroupStats>{"others", other}}) {
      h << "<tr" << (row == 0 ? " class='dir'" : "") << ">";
      if (row == 0)
        h << "<td rowspan='2'>" << m.name << "</td><td rowspan='2'>" << m.unit << "</td>";
      h << "<td>" << group << "</td><td><b>" << fixed(g.median, m.digits) << "</b></td><td>"
        << fixed(g.mean, m.digits) << "</td><td>" << fixed(g.min, m.digits) << "</td><td>"
        << fixed(g.max, m.digits) << "</td><td>" << g.count
        << (g.missing ? " (+" + std::to_string(g.missing) + " without a value)" : "") << "</td>";
      if (row == 0) h << "<td rowspan='2'>" << verdict << "</td>";
      h << "</tr>";
      ++row;
    }
  }
  h << "</table>";
}

// Inputs: plant-friendliness (SPEC §5), one row per design.
void inputs_section(std::ostream& h, const CampaignResult& r) {
  h << "<h2>Inputs: plant-friendliness (SPEC §5)</h2><table><tr><th>#</th><th>design</th>"
       "<th>samples</th><th>duration [h min]</th><th>CF period [–]</th><th>CF per input, "
       "period [–]</th><th>CF experiment [–]</th><th>PIPS avg [%]</th><th>limit scale "
       "[–]</th></tr>";
  for (const Experiment& e : r.experiments) {
    h << "<tr" << (directional(e.name) ? " class='dir'" : "") << "><td>" << e.number << ' '
      << e.name << "</td><td>" << (directional(e.name) ? "directional" : "inputs") << "</td><td>"
      << e.U.rows() << "</td><td>"
      << duration_text(static_cast<double>(e.U.rows()) * e.sample_time_min) << "</td><td>"
      << fixed(e.cf_period_avg) << "</td><td>" << per_input_crest_factors(e.U) << "</td><td>"
      << fixed(e.cf_avg) << "</td><td>" << fixed(e.pips_avg, 1) << "</td><td>"
      << fixed(e.limit_scale, 4) << "</td></tr>";
  }
  h << "</table>";
}

// Models: fit, cross-fit and the loss against the truth, one row per model.
void models_section(std::ostream& h, const CampaignResult& r, const ReportArtifacts& artifacts) {
  h << "<h2>Models: fit and cross-fit (5.5.1, SPEC §6)</h2><p class='note'>"
    << (r.truth_known
            ? "A cross-fit is bounded by the validation run's noise, which no model predicts: "
              "'truth' is the true plant's fit on the same run (same rows, same rule), the most "
              "any model can reach there. The <b>loss against the truth</b>, truth − cross-fit "
              "in points of fit %, is what a model loses through being wrong, whatever the "
              "run's noise (host/measures/cross_fit.hpp); the worst cross-fit mostly names the "
              "noisiest run ('worst on')."
            : "Measured data: no truth is known, so 'worst on' names the run that bounds each "
              "model's worst cross-fit — often the noisiest run, which bounds every model "
              "alike.")
    << "</p><table><tr><th>model from</th><th>own fit [%]</th><th>truth, own run [%]</th>"
       "<th>cross-fit avg [%]</th><th>best [%]</th><th>worst [%]</th><th>worst on</th>"
       "<th>truth there [%]</th><th>loss avg [points]</th><th>loss worst [points]</th>"
       "<th>loss worst on</th><th>run log</th><th>model file</th></tr>";
  for (std::size_t k = 0; k < r.experiments.size(); ++k) {
    const Experiment& e = r.experiments[k];
    h << "<tr" << (directional(e.name) ? " class='dir'" : "") << "><td>" << e.name << "</td><td>"
      << fixed(e.fit_avg, 1) << "</td><td>" << fixed(e.truth_fit, 1) << "</td><td>"
      << fixed(e.crossfit_avg, 1) << "</td><td>" << fixed(e.crossfit_best, 1) << "</td><td>"
      << fixed(e.crossfit_worst, 1) << "</td><td>" << run_name(r, e.crossfit_worst_on)
      << "</td><td>" << fixed(e.truth_fit_on_worst, 1) << "</td><td>" << fixed(e.loss_avg, 2)
      << "</td><td>" << fixed(e.loss_worst, 2) << "</td><td>" << run_name(r, e.loss_worst_on)
      << "</td><td>" << link_to(artifacts.run_logs, k, "run.csv") << "</td><td>"
      << link_to(artifacts.models, k, "model.json") << "</td></tr>";
  }
  h << "</table>";
}

// The identified G(0)'s singular values beside the true ones.
void directions_section(std::ostream& h, const CampaignResult& r, const std::string& out_unit,
                        const std::string& in_unit) {
  const Eigen::Index n = r.true_gain.singular_values.size();
  h << "<h2>Identified gain directions</h2><p class='note'>Singular values of the identified "
       "G(0) in "
    << gain_unit(out_unit, in_unit) << "; κ = σ₁/σₙ [–].</p><table><tr><th>model from</th>";
  for (Eigen::Index i = 0; i < n; ++i) h << "<th>σ" << i + 1 << "</th>";
  h << "<th>κ [–]</th></tr><tr><td><b>true</b></td>";
  for (Eigen::Index i = 0; i < n; ++i)
    h << "<td><b>" << general(r.true_gain.singular_values(i)) << "</b></td>";
  h << "<td><b>" << general(r.true_gain.condition_number) << "</b></td></tr>";
  for (const Experiment& e : r.experiments) {
    h << "<tr" << (directional(e.name) ? " class='dir'" : "") << "><td>" << e.name << "</td>";
    for (Eigen::Index i = 0; i < n; ++i) {
      h << "<td>" << (e.identified.gain ? general(e.identified.gain->singular_values(i)) : "–")
        << "</td>";
    }
    h << "<td>" << (e.identified.gain ? general(e.identified.gain->condition_number) : "–")
      << "</td></tr>";
  }
  h << "</table>";
}

// Output balance (5.5.2, 6.2.1), noise-free and noisy.
void balance_section(std::ostream& h, const CampaignResult& r) {
  const Eigen::Index n = r.true_gain.singular_values.size();
  h << "<h2>Output balance (5.5.2, 6.2.1)</h2><p class='note'>Standard deviation of the "
       "projections w_iᵀy on the true output gain directions "
    << common_unit(r.output_units)
    << ", their ratio min/max [–], and Υ = det(corr(Y)) [–]: on the noise-free outputs (a "
       "property of the excitation), and on the noisy outputs beside them.</p><table><tr><th>"
       "design</th>";
  for (Eigen::Index i = 0; i < n; ++i) h << "<th>std w" << i + 1 << "ᵀy (noise-free)</th>";
  h << "<th>ratio noise-free</th><th>ratio noisy</th><th>Υ noise-free</th><th>Υ noisy</th></tr>";
  for (const Experiment& e : r.experiments) {
    h << "<tr" << (directional(e.name) ? " class='dir'" : "") << "><td>" << e.name << "</td>";
    for (Eigen::Index i = 0; i < e.balance_clean.projection_std.size(); ++i)
      h << "<td>" << general(e.balance_clean.projection_std(i)) << "</td>";
    h << "<td>" << fixed(e.balance_clean.ratio) << "</td><td>" << fixed(e.balance_noisy.ratio)
      << "</td><td>" << general(e.balance_clean.upsilon) << "</td><td>"
      << general(e.balance_noisy.upsilon) << "</td></tr>";
  }
  h << "</table>";
}

// The campaign's two summary figures.
void figures_section(std::ostream& h) {
  h << "<h2>Figures</h2><h3>Output projections, strongest against weakest direction</h3>"
       "<img src='figures/projections.svg' alt='projections'>"
       "<h3>Singular values of G(jω): true plant and identified models</h3><img "
       "src='figures/sigma.svg' alt='sigma'>";
}

// Model quality per design: parameters, step responses with bands, residual tests.
void quality_section(std::ostream& h, const CampaignResult& r, const ReportArtifacts& artifacts,
                     const StepHorizon& steps) {
  h << "<h2>Model quality, per design</h2><p class='note'>For each model: its parameters with "
       "1σ standard errors (σ̂√diag((JᵀJ)⁻¹), SSE/(N−P), host/identify/README.md); its "
       "unit-step responses with a ±2σ band obtained by <b>linearised propagation</b> of the "
       "element's 4 × 4 parameter covariance (σ_s(t)² = gᵀCg, g = ∂s/∂θ; a parameter on its "
       "bound counts as exact, the covariance between elements of a row is left out) over "
       "the first "
    << duration_text(steps.samples * steps.sample_time_min)
    << " (the median settling time of the models), against the true plant's unit step "
       "(dashed); measured against predicted outputs; and the residual autocorrelation and "
       "cross-correlation with every input for lags up to "
    << kResidualLags
    << " samples, with the 99 % limits ±2.58/√N of a white residual independent of the "
       "inputs. The standard errors assume the model structure is right.</p>";
  for (std::size_t k = 0; k < r.experiments.size(); ++k) {
    const Experiment& e = r.experiments[k];
    h << "<details><summary>" << e.number << ' ' << e.name << ": own fit " << fixed(e.fit_avg, 1)
      << " %, worst cross-fit " << fixed(e.crossfit_worst, 1) << " % (on "
      << run_name(r, e.crossfit_worst_on) << ")"
      << (std::isfinite(e.loss_avg) ? ", loss against the truth " + fixed(e.loss_avg, 2) +
                                          " points average, " + fixed(e.loss_worst, 2) + " worst"
                                    : std::string())
      << "</summary><p>Run log: " << link_to(artifacts.run_logs, k, "run.csv")
      << ", model: " << link_to(artifacts.models, k, "model.json") << "</p>"
      << parameter_table_html(e, r);
    for (const auto& [view, alt] :
         {std::pair<const char*, const char*>{"-steps.svg", " step responses"},
          {"-fit.svg", " measured and predicted"},
          {"-residuals.svg", " residual correlations"}}) {
      h << deferred_image("figures/" + e.name + view, e.name + alt);
    }
    h << "</details>";
  }
  // Loads a section's figures when it is opened (see deferred_image).
  h << "<script>const load=d=>{if(d.open)for(const i of d.querySelectorAll('img[data-src]'))"
       "{i.src=i.dataset.src;i.removeAttribute('data-src')}};for(const d of "
       "document.querySelectorAll('details')){load(d);d.addEventListener('toggle',()=>load(d))}"
       "</script>";
}

// Every experiment's inputs and outputs.
void io_section(std::ostream& h, const CampaignResult& r) {
  h << "<h2>Inputs and outputs of each experiment</h2>";
  for (const Experiment& e : r.experiments)
    h << "<img src='figures/" << e.name << ".svg' alt='" << e.name << "'>";
  h << "</body></html>\n";
}

}  // namespace

const char* report_style() {
  return "body{font-family:sans-serif;max-width:1150px;margin:2em auto;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px "
         "8px;text-align:right}"
         "th{background:#eef}td:first-child,th:first-child{text-align:left}tr.dir "
         "td{background:#eef5ff}"
         "img{max-width:100%;border:1px solid #ddd;margin:.5em 0}.note{color:#555}"
         "details{border:1px solid #ccd;margin:.4em 0;padding:.3em .6em}"
         "summary{cursor:pointer;font-weight:bold}table.params td{text-align:left}";
}

void write_summary(const CampaignResult& r, const std::filesystem::path& dir) {
  nlohmann::json experiments = nlohmann::json::array();
  for (const Experiment& e : r.experiments) {
    experiments.push_back(
        {{"name", e.name},
         {"number", e.number},
         {"samples", e.U.rows()},
         {"cf_avg", number(e.cf_avg)},
         {"cf_period_avg", number(e.cf_period_avg)},
         {"limit_scale", number(e.limit_scale)},
         {"pips_avg", number(e.pips_avg)},
         {"fit_avg", number(e.fit_avg)},
         {"crossfit_avg", number(e.crossfit_avg)},
         {"crossfit_best", number(e.crossfit_best)},
         {"crossfit_worst", number(e.crossfit_worst)},
         {"singular_values",
          e.identified.gain ? vector(e.identified.gain->singular_values) : nlohmann::json(nullptr)},
         {"projection_std", vector(e.balance_clean.projection_std)},
         {"ratio", number(e.balance_clean.ratio)},
         {"upsilon", number(e.balance_clean.upsilon)},
         {"projection_std_noisy", vector(e.balance_noisy.projection_std)},
         {"ratio_noisy", number(e.balance_noisy.ratio)},
         {"upsilon_noisy", number(e.balance_noisy.upsilon)},
         {"truth_fit", number(e.truth_fit)},
         {"crossfit_worst_on", run_name_json(r, e.crossfit_worst_on)},
         {"truth_fit_on_worst", number(e.truth_fit_on_worst)},
         {"loss_avg", number(e.loss_avg)},
         {"loss_worst", number(e.loss_worst)},
         {"loss_worst_on", run_name_json(r, e.loss_worst_on)}});
  }
  const nlohmann::json j = {
      {"plant", r.plant},
      {"design_gain_source", r.design_gain_source},
      {"conventions", conventions(r)},
      {"true_singular_values", vector(r.true_gain.singular_values)},
      {"design_singular_values", vector(r.design_gain.singular_values)},
      {"step_test_singular_values",
       r.step_gain ? vector(r.step_gain->singular_values) : nlohmann::json(nullptr)},
      {"structure", structure_name(r)},
      {"truth_known", r.truth_known},
      {"experiments", experiments}};
  write_whole_file(dir / "summary.json", j.dump(2) + '\n');
}

void write_report(const CampaignResult& r, const sim::Plant& plant,
                  const std::filesystem::path& dir, const ReportArtifacts& artifacts, int threads) {
  const StepHorizon steps = draw_figures(r, plant, dir, threads);
  const std::string out_unit = common_unit_token(r.output_units);
  const std::string in_unit = common_unit_token(r.input_units);
  std::ostringstream h;
  head_section(h, r, out_unit, in_unit);
  metrics_section(h, r);
  inputs_section(h, r);
  models_section(h, r, artifacts);
  directions_section(h, r, out_unit, in_unit);
  balance_section(h, r);
  figures_section(h);
  quality_section(h, r, artifacts, steps);
  io_section(h, r);
  write_whole_file(dir / "index.html", h.str());
}

}  // namespace excite::host
