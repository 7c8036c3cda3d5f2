// SPDX-License-Identifier: MIT
#include "host/campaign/model_views.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "host/campaign/gnuplot.hpp"
#include "host/campaign/plot_points.hpp"
#include "host/export/step_response.hpp"
#include "host/identify/residuals.hpp"
#include "host/identify/validate.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host {
namespace {

std::string format(const char* pattern, double v) {
  if (std::isnan(v)) return "–";
  if (std::isinf(v)) return "∞";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, v);
  return buffer;
}

std::string with_error(double value, double se, bool at_bound) {
  if (std::isnan(value)) return "–";
  std::string s = format("%.4g", value);
  if (at_bound) return s + " (on its bound)";
  if (std::isnan(se)) return s;
  return s + " ± " + format("%.2g", se);
}

std::string unit_of(const std::vector<std::string>& units, int i) {
  return i < static_cast<int>(units.size()) ? units[static_cast<std::size_t>(i)] : "-";
}

std::string name_of(const std::vector<std::string>& names, int i) {
  return names.at(static_cast<std::size_t>(i));
}

// A tic step of 1, 2 or 5 × 10^k giving at most about five tics over `span`.
double tic_step(double span) {
  const double raw = span / 5.0;
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double m : {1.0, 2.0, 5.0}) {
    if (m * decade >= raw) return m * decade;
  }
  return 10.0 * decade;
}

std::string axis_unit(const std::string& unit) {
  return unit == "-" ? "[–]" : "[" + unit + "]";
}

// The step figure's data blocks, per element el: 3·el the ±2σ band as a closed outline
// (lower edge forward, upper edge back), 3·el+1 the model's step, 3·el+2 the true step (empty
// if unknown); each simplified within half a pixel of its panel. Returns, per element,
// whether its band is known.
std::vector<bool> write_step_data(const IdentifiedModel& m, const Eigen::MatrixXd& truth,
                                  const std::vector<double>& t, double divisor,
                                  const std::filesystem::path& figures, const std::string& data) {
  std::vector<bool> band_known;
  std::ostringstream out;
  for (int o = 0; o < m.outputs; ++o) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& est = m.element(o, i);
      Polyline band, model, true_step;
      bool known = false;
      if (est.estimated()) {
        const StepBand b = step_band(est, t);
        known = true;
        Polyline upper;
        for (std::size_t k = 0; k < t.size(); ++k) {
          const double x = t[k] / divisor, s = b.response[k], w = 2.0 * b.sigma[k];
          if (!std::isfinite(w)) known = false;
          model.push_back({x, s});
          band.push_back({x, std::isfinite(w) ? s - w : s});
          upper.push_back({x, std::isfinite(w) ? s + w : s});
        }
        band.insert(band.end(), upper.rbegin(), upper.rend());
      }
      const Eigen::Index column = o * m.inputs + i;
      for (std::size_t k = 0; k < t.size() && column < truth.cols(); ++k) {
        const auto kk = static_cast<Eigen::Index>(k);
        if (kk < truth.rows()) true_step.push_back({t[k] / divisor, truth(kk, column)});
      }
      const PixelFrame frame = frame_of({band, model, true_step}, 260.0, 210.0);
      write_block(out, simplify(band, frame));
      write_block(out, simplify(model, frame));
      write_block(out, simplify(true_step, frame));
      band_known.push_back(known);
    }
  }
  write_figure_source(figures, data, out.str());
  return band_known;
}

// The step-response matrix: one panel per CV × MV, model with its ±2σ band, truth dashed.
std::string step_script(const Experiment& e, const CampaignResult& r, const Eigen::MatrixXd& truth,
                        int horizon, const std::filesystem::path& figures) {
  const IdentifiedModel& m = e.identified.model;
  const double T = e.sample_time_min;
  std::vector<double> t;
  for (int k = 0; k <= horizon; ++k) t.push_back(k * T);
  const auto [time_label, divisor] = time_axis(horizon * T);
  const std::string data = source_name(e.name + "-steps.dat");
  const std::vector<bool> band_known = write_step_data(m, truth, t, divisor, figures, data);
  const int p = m.outputs, n = m.inputs;
  const std::string script = source_name(e.name + "-steps.gp");
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size " << std::max(700, 260 * n) << ','
     << std::max(420, 210 * p + 60) << " dynamic font 'sans,10'\nset output "
     << gnuplot_string(e.name + "-steps.svg") << "\nset multiplot layout " << p << ',' << n
     << " title "
     << gnuplot_string(e.name + ": unit steps, model ±2σ (blue)" +
                       std::string(truth.size() ? ", true plant (black dashed)" : ""))
     << "\nset grid\nunset key\nset xlabel " << gnuplot_string(time_label) << "\nset xtics "
     << tic_step(horizon * T / divisor) << '\n';
  const std::string file = gnuplot_string(data);
  for (int o = 0; o < p; ++o) {
    for (int i = 0; i < n; ++i) {
      const int el = o * n + i;
      gp << "set title "
         << gnuplot_string(
                name_of(r.output_names, o) + " ← " + name_of(r.input_names, i) +
                (band_known[static_cast<std::size_t>(el)] ? "" : " (band not determined)"))
         << "\nset ylabel "
         << gnuplot_string(
                i == 0 ? "s(t) " + gain_unit(unit_of(r.output_units, o), unit_of(r.input_units, i))
                       : "")
         << "\nplot " << file << " index " << 3 * el
         << " with filledcurves closed lc rgb '#a8c4f0' notitle, " << file << " index "
         << 3 * el + 1 << " with lines lw 2 lc rgb '#1f4e9c' notitle";
      if (truth.size() != 0) {
        gp << ", " << file << " index " << 3 * el + 2
           << " with lines lw 1.5 dt 2 lc rgb 'black' notitle";
      }
      gp << '\n';
    }
  }
  gp << "unset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

// Measured against predicted, one panel per output; each curve as its panel shows it: the
// lowest and highest sample per pixel column, simplified within half a pixel.
std::string fit_script(const Experiment& e, const CampaignResult& r, const Eigen::MatrixXd& Y_hat,
                       const std::filesystem::path& figures) {
  constexpr int kColumns = 850;  // pixel columns of a panel's plot area (1000 px wide)
  const Eigen::Index N = e.Y.rows();
  const auto [time_label, divisor] = time_axis(static_cast<double>(N) * e.sample_time_min);
  const std::string data = source_name(e.name + "-fit.dat");
  {
    // Blocks: 2·o measured, 2·o+1 the model's simulation, per output o.
    std::vector<double> t;
    for (Eigen::Index k = 0; k < N; ++k)
      t.push_back(static_cast<double>(k) * e.sample_time_min / divisor);
    std::ostringstream out;
    for (Eigen::Index o = 0; o < e.Y.cols(); ++o) {
      const Eigen::VectorXd measured = e.Y.col(o), model = Y_hat.col(o);
      const std::vector<double> ym(measured.data(), measured.data() + N);
      const std::vector<double> yp(model.data(), model.data() + N);
      const Polyline a = min_max_columns(t, ym, kColumns), b = min_max_columns(t, yp, kColumns);
      const PixelFrame frame = frame_of({a, b}, kColumns, 200.0);
      write_block(out, simplify(a, frame));
      write_block(out, simplify(b, frame));
    }
    write_figure_source(figures, data, out.str());
  }
  const auto p = static_cast<int>(e.Y.cols());
  const std::string script = source_name(e.name + "-fit.gp");
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 1000," << 180 * p + 80
     << " dynamic font 'sans,10'\nset output " << gnuplot_string(e.name + "-fit.svg")
     << "\nset multiplot layout " << p << ",1 title "
     << gnuplot_string(e.name + ": measured outputs (grey) and the model's simulation (blue)" +
                       (N > 2 * kColumns ? ", min and max per pixel column" : ""))
     << "\nset grid\nset key outside right top\nset xlabel " << gnuplot_string(time_label) << '\n';
  const std::string file = gnuplot_string(data);
  for (int o = 0; o < p; ++o) {
    const double fit = e.identified.fits.at(static_cast<std::size_t>(o)).fit_percent;
    gp << "set ylabel "
       << gnuplot_string("Δ" + name_of(r.output_names, o) + " " +
                         axis_unit(unit_of(r.output_units, o)))
       << "\nset title "
       << gnuplot_string(name_of(r.output_names, o) + ": fit " + format("%.1f", fit) + " % (5.5.1)")
       << "\nplot " << file << " index " << 2 * o
       << " with lines lc rgb '#999999' title 'measured', " << file << " index " << 2 * o + 1
       << " with lines lw 1.5 lc rgb '#1f4e9c' title 'model'\n";
  }
  gp << "unset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

// Residual autocorrelation and cross-correlation with every input, 99 % limits dashed red.
std::string residual_script(const Experiment& e, const CampaignResult& r,
                            const Eigen::MatrixXd& Y_hat, const std::filesystem::path& figures) {
  const auto p = static_cast<int>(e.Y.cols());
  const auto n = static_cast<int>(e.U.cols());
  const int L = std::min<int>(kResidualLags, static_cast<int>(e.Y.rows()) - 1);
  const std::string data = source_name(e.name + "-residuals.dat");
  double limit = 0.0;
  {
    std::vector<ResidualCorrelation> rc;
    for (int o = 0; o < p; ++o) {
      const Eigen::VectorXd residual = e.Y.col(o) - Y_hat.col(o);
      rc.push_back(residual.allFinite()
                       ? residual_correlation(residual, e.U, L)
                       : ResidualCorrelation{L, Eigen::VectorXd::Zero(L + 1),
                                             Eigen::MatrixXd::Zero(2 * L + 1, n), 0.0});
      limit = std::max(limit, rc.back().limit_99);
    }
    std::ostringstream out;  // lag, then per output: auto (NaN for τ < 0), cross × n
    for (int tau = -L; tau <= L; ++tau) {
      out << tau * e.sample_time_min;
      for (int o = 0; o < p; ++o) {
        const ResidualCorrelation& c = rc[static_cast<std::size_t>(o)];
        out << ' ' << (tau >= 0 ? c.auto_correlation(tau) : NAN);
        for (int i = 0; i < n; ++i) out << ' ' << c.cross_correlation(tau + L, i);
      }
      out << '\n';
    }
    write_figure_source(figures, data, out.str());
  }
  const std::string script = source_name(e.name + "-residuals.gp");
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size " << 230 * (n + 1) + 40 << ',' << 190 * p + 80
     << " dynamic font 'sans,9'\nset output " << gnuplot_string(e.name + "-residuals.svg")
     << "\nset multiplot layout " << p << ',' << n + 1 << " title "
     << gnuplot_string(e.name +
                       ": residual autocorrelation (left) and cross-correlation with "
                       "each input; dashed: 99 % limits ±2.58/√N = ±" +
                       format("%.3g", limit))
     << "\nset grid\nunset key\nset samples 2\nset xlabel 'lag [min]'\nset yrange [-1:1]\nset "
        "xtics "
     << tic_step(2.0 * L * e.sample_time_min) << '\n';
  const std::string file = gnuplot_string(data);
  const int per_output = n + 1;
  for (int o = 0; o < p; ++o) {
    for (int c = 0; c <= n; ++c) {
      const std::string what = c == 0 ? "r_{ee}, e = residual of " + name_of(r.output_names, o)
                                      : "r_{ue}: " + name_of(r.input_names, c - 1) + " × e(" +
                                            name_of(r.output_names, o) + ")";
      gp << "set title " << gnuplot_string(what) << "\nset ylabel "
         << gnuplot_string(c == 0 ? "correlation [–]" : "") << "\nset xrange ["
         << (c == 0 ? 0.0 : -L * e.sample_time_min) << ':' << L * e.sample_time_min << "]\nplot "
         << file << " using 1:" << 2 + o * per_output + c
         << " with impulses lw 2 lc rgb '#1f4e9c', " << limit
         << " with lines dt 2 lc rgb '#c03030', " << -limit
         << " with lines dt 2 lc rgb '#c03030'\n";
    }
  }
  gp << "unset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

}  // namespace

std::string gain_unit(const std::string& output_unit, const std::string& input_unit) {
  if (output_unit == "-" && input_unit == "-") return "[–]";
  return "[" + output_unit + " per " + input_unit + "]";
}

std::pair<std::string, double> time_axis(double longest_min) {
  if (longest_min > 600.0) return {"t [h]", 60.0};
  return {"t [min]", 1.0};
}

std::string duration_text(double minutes) {
  if (minutes < 120.0) return format("%.0f", minutes) + " min";
  const auto whole = static_cast<long>(std::lround(minutes));
  return std::to_string(whole / 60) + " h " + std::to_string(whole % 60) + " min";
}

Eigen::MatrixXd true_unit_steps(sim::Plant& plant, int samples, double sample_time_min) {
  const int n = plant.inputs(), p = plant.outputs();
  Eigen::MatrixXd steps(samples + 1, p * n);
  const Eigen::VectorXd baseline = plant.input_baseline();
  for (int i = 0; i < n; ++i) {
    const double size = 1e-3 * std::max(1.0, std::abs(baseline(i)));
    Eigen::MatrixXd du = Eigen::MatrixXd::Zero(samples + 1, n);
    du.col(i).setConstant(size);
    const Eigen::MatrixXd dy = plant.simulate(du, sample_time_min);
    for (int o = 0; o < p; ++o) steps.col(o * n + i) = dy.col(o) / size;
  }
  return steps;
}

int report_step_horizon(const CampaignResult& r) {
  std::vector<int> horizons;
  Eigen::Index shortest = std::numeric_limits<Eigen::Index>::max();
  for (const Experiment& e : r.experiments) {
    horizons.push_back(settling_samples(e.identified.model));
    shortest = std::min(shortest, e.U.rows());
  }
  if (horizons.empty()) return 1;
  std::nth_element(horizons.begin(), horizons.begin() + static_cast<long>(horizons.size() / 2),
                   horizons.end());
  const int median = horizons[horizons.size() / 2];
  return static_cast<int>(
      std::clamp<Eigen::Index>(median, 1, std::max<Eigen::Index>(1, shortest - 1)));
}

std::vector<std::string> write_model_view_scripts(const Experiment& e, const CampaignResult& r,
                                                  const Eigen::MatrixXd& truth, int horizon_samples,
                                                  const std::filesystem::path& figures) {
  const Eigen::MatrixXd Y_hat = simulate(e.identified.model, e.U);
  return {step_script(e, r, truth, horizon_samples, figures), fit_script(e, r, Y_hat, figures),
          residual_script(e, r, Y_hat, figures)};
}

std::string parameter_table_html(const Experiment& e, const CampaignResult& r) {
  const IdentifiedModel& m = e.identified.model;
  std::ostringstream h;
  h << "<table class='params'><tr><th>CV ← MV</th><th>grade</th><th>status</th><th>K [CV unit "
       "per MV unit]</th><th>T<sub>d</sub> [min]</th><th>T<sub>p1</sub> "
       "[min]</th><th>T<sub>p2</sub> "
       "[min]</th><th>structure, its other parameters</th></tr>";
  for (int o = 0; o < m.outputs; ++o) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& est = m.element(o, i);
      const auto bound = [&](int k) {
        return est.at_bound[static_cast<std::size_t>(k)] != Bound::none;
      };
      // A parameter of the element's structure with its error; "–" for one it does not have.
      const auto parameter_cell = [&](int k) {
        if (est.estimated() && !is_free(est.value.structure, k)) return std::string("–");
        return with_error(est.value[k], est.std_error[k], bound(k));
      };
      // The grade (host/identify/grade.hpp), what kept it from A as the cell's tooltip.
      std::string why;
      for (const char c : est.grade_reason)
        why += c == '\'' ? std::string("&#39;") : std::string(1, c);
      h << "<tr><td>" << name_of(r.output_names, o) << " ← " << name_of(r.input_names, i)
        << "</td><td title='" << why << "'>" << to_string(est.grade) << "</td><td>"
        << to_string(est.status) << "</td><td>"
        << with_error(est.value.gain, est.std_error.gain, bound(kGain)) << "</td><td>"
        << with_error(est.value.delay_min, est.std_error.delay_min, bound(kDelay)) << "</td><td>"
        << parameter_cell(kTp1) << "</td><td>" << parameter_cell(kTp2) << "</td><td>"
        << (est.estimated() ? to_string(est.value.structure) : "–");
      for (const int k : {kZero, kNatural, kDamping}) {
        if (est.estimated() && is_free(est.value.structure, k)) {
          h << ", " << parameter_name(static_cast<Parameter>(k)) << " = " << parameter_cell(k);
        }
      }
      h << "</td></tr>";
    }
  }
  h << "</table>";
  if (const auto& u = e.identified.gain_uncertainty) {
    // How well G(0)'s gain directions are known (host/identify/gain_uncertainty.hpp).
    h << "<table class='params'><tr><th>direction i</th><th>σ<sub>i</sub> ± SE</th><th>input "
         "direction v<sub>i</sub>: angle ± [°]</th><th>output direction w<sub>i</sub>: angle ± "
         "[°]</th></tr>";
    for (Eigen::Index i = 0; i < u->singular_values.size(); ++i) {
      h << "<tr><td>" << i + 1 << "</td><td>"
        << with_error(u->singular_values(i), u->singular_value_se(i), false) << "</td><td>"
        << format("%.2g", u->input_angle_se_deg(i)) << "</td><td>"
        << format("%.2g", u->output_angle_se_deg(i)) << "</td></tr>";
    }
    h << "</table>";
    if (!u->principal_minors.empty()) {
      const PrincipalMinor& det = u->principal_minors.back();
      h << "<p>Principal minors of G(0): " << u->sign_uncertain_minors << " of "
        << u->principal_minors.size()
        << " could change sign within their 95 % interval; det G(0) = "
        << with_error(det.value, det.std_error, false)
        << (det.sign_uncertain ? " — its sign is not known: integral controllability at risk" : "")
        << ".</p>";
    }
  }
  return h.str();
}

}  // namespace excite::host
