// SPDX-License-Identifier: MIT
#include "host/campaign/report_figures.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <complex>
#include <iomanip>
#include <limits>
#include <sstream>

#include "host/campaign/gnuplot.hpp"
#include "host/campaign/model_views.hpp"
#include "host/campaign/plot_points.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/parallel.hpp"

namespace excite::host {
namespace {

// Pixels of one panel's plot area (generous: a larger frame only keeps more points).
constexpr double kSeriesWidthPx = 700.0, kSeriesHeightPx = 220.0;  // <name>.svg, 900 × 520
constexpr double kSmallWidthPx = 260.0, kSmallHeightPx = 220.0;    // 4-column small multiples
constexpr int kCloudWidth = 200, kCloudHeight = 170;  // raster cells of a projection panel

// The identified model's G(jω) from its elements (any structure, element.hpp).
Eigen::MatrixXcd model_response(const IdentifiedModel& m, double omega) {
  Eigen::MatrixXcd g(m.outputs, m.inputs);
  for (int o = 0; o < m.outputs; ++o) {
    for (int i = 0; i < m.inputs; ++i) {
      const ElementEstimate& e = m.element(o, i);
      g(o, i) = e.estimated() ? to_term(e.value, m.sample_time_min).frequency_response(omega)
                              : std::complex<double>(std::numeric_limits<double>::quiet_NaN());
    }
  }
  return g;
}

// A column of samples as a curve of what an experiment's panel shows (simplified within half
// a pixel when written).
Polyline series(const Eigen::VectorXd& v, double dt, bool hold) {
  return time_series_curve(v, dt, hold, kSeriesWidthPx);
}

// Inputs and outputs of one experiment over time, two panels.
std::string plot_experiment(const Experiment& e, const CampaignResult& r,
                            const std::filesystem::path& figures) {
  const std::string data = source_name(e.name + ".dat");
  const auto [time_label, divisor] = time_axis(static_cast<double>(e.U.rows()) * e.sample_time_min);
  const double dt = e.sample_time_min / divisor;
  {
    // Blocks: the inputs (index 0 … n−1), then the outputs (index n … n+p−1).
    std::vector<Polyline> inputs, outputs;
    for (Eigen::Index j = 0; j < e.U.cols(); ++j) inputs.push_back(series(e.U.col(j), dt, true));
    for (Eigen::Index j = 0; j < e.Y.cols(); ++j) outputs.push_back(series(e.Y.col(j), dt, false));
    std::ostringstream out;
    for (auto* panel : {&inputs, &outputs}) {
      const PixelFrame frame = frame_of(*panel, kSeriesWidthPx, kSeriesHeightPx);
      for (const Polyline& c : *panel) write_block(out, simplify(c, frame));
    }
    write_figure_source(figures, data, out.str());
  }
  const std::string script = source_name(e.name + ".gp");
  std::ostringstream gp;
  gp << "set terminal svg size 900,520 dynamic font 'sans,11'\nset output "
     << gnuplot_string(e.name + ".svg") << "\nset multiplot layout 2,1 title "
     << gnuplot_string(e.name + ": inputs (top) and outputs (bottom)") << '\n'
     << "set xlabel " << gnuplot_string(time_label) << "\nset grid\nset key outside right\n"
     << "set ylabel " << gnuplot_string("Δu " + common_unit(r.input_units)) << '\n';
  gp << "plot";
  for (Eigen::Index j = 0; j < e.U.cols(); ++j) {
    gp << (j ? ", " : " ") << gnuplot_string(data) << " index " << j << " with lines title "
       << gnuplot_string(r.input_names[static_cast<std::size_t>(j)]);
  }
  gp << "\nset ylabel " << gnuplot_string("Δy " + common_unit(r.output_units)) << "\nplot";
  for (Eigen::Index j = 0; j < e.Y.cols(); ++j) {
    gp << (j ? ", " : " ") << gnuplot_string(data) << " index " << e.U.cols() + j
       << " with lines title " << gnuplot_string(r.output_names[static_cast<std::size_t>(j)]);
  }
  gp << "\nunset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

// Projections of the noise-free outputs on the strongest and weakest output directions, per
// experiment, each panel on its own scale (the designs differ by orders of magnitude). Every
// sample marks its cell of a kCloudWidth × kCloudHeight raster, drawn as an image: no sample
// is left out, and the SVG holds one small PNG per panel instead of a dot per sample.
std::string plot_projections(const CampaignResult& r, const std::filesystem::path& figures) {
  const Eigen::Index last = r.true_gain.output_directions.cols() - 1;
  const std::string unit = common_unit(r.output_units);
  const auto rows = static_cast<int>((r.experiments.size() + 3) / 4);
  const std::string script = source_name("projections.gp");
  std::ostringstream gp;
  gp << std::setprecision(10);  // the raster's origin and cell size
  gp << "set encoding utf8\nset terminal svg size 1150," << 250 * rows + 60
     << " dynamic font 'sans,9'\nset output " << gnuplot_string("projections.svg")
     << "\nset multiplot layout " << rows << ",4 title "
     << gnuplot_string(
            "noise-free outputs projected on the true output directions: w_1ᵀy "
            "(strongest) against w_" +
            std::to_string(last + 1) + "ᵀy (weakest); each panel on its own scale")
     << "\nunset key\nunset colorbox\nset grid front\nset xlabel "
     << gnuplot_string("w_1ᵀy " + unit) << "\nset ylabel "
     << gnuplot_string("w_" + std::to_string(last + 1) + "ᵀy " + unit)
     << "\nset format x '%.2g'\nset format y '%.2g'\nset xtics rotate by -30\n";
  for (const Experiment& e : r.experiments) {
    const Eigen::MatrixXd p = e.Y_clean * r.true_gain.output_directions;
    const Eigen::VectorXd x = p.col(0), y = p.col(last);
    double x0 = x.minCoeff(), x1 = x.maxCoeff(), y0 = y.minCoeff(), y1 = y.maxCoeff();
    const auto widen = [](double& lo, double& hi) {
      const double pad = hi > lo ? 0.02 * (hi - lo) : std::max(1e-12, 0.02 * std::abs(lo) + 1e-12);
      lo -= pad;
      hi += pad;
    };
    widen(x0, x1);
    widen(y0, y1);
    const double dx = (x1 - x0) / kCloudWidth, dy = (y1 - y0) / kCloudHeight;
    // RGBA bytes, row by row from the bottom (y0) up: a sample's cell opaque blue, the rest
    // transparent (gnuplot's binary array, read without parsing text).
    std::string cells(static_cast<std::size_t>(kCloudWidth * kCloudHeight * 4), '\0');
    for (Eigen::Index k = 0; k < p.rows(); ++k) {
      if (!std::isfinite(x(k)) || !std::isfinite(y(k))) continue;
      const int cx = std::clamp(static_cast<int>((x(k) - x0) / dx), 0, kCloudWidth - 1);
      const int cy = std::clamp(static_cast<int>((y(k) - y0) / dy), 0, kCloudHeight - 1);
      const auto at = static_cast<std::size_t>((cy * kCloudWidth + cx) * 4);
      cells[at] = '\x1f';
      cells[at + 1] = '\x4e';
      cells[at + 2] = '\x9c';
      cells[at + 3] = '\xff';
    }
    const std::string data = source_name(e.name + ".cells");
    write_figure_source(figures, data, cells);
    gp << "set title " << gnuplot_string(std::to_string(e.number) + " " + e.name)
       << "\nset xrange [" << x0 << ':' << x1 << "]\nset yrange [" << y0 << ':' << y1 << "]\nplot "
       << gnuplot_string(data) << " binary array=(" << kCloudWidth << ',' << kCloudHeight
       << ") dx=" << dx << " dy=" << dy << " origin=(" << x0 + 0.5 * dx << ',' << y0 + 0.5 * dy
       << ") format='%uchar' with rgbalpha\n";
  }
  gp << "unset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

// Singular values of G(jω): the true plant against every identified model.
std::string plot_frequency(const CampaignResult& r, const sim::Plant& plant,
                           const std::filesystem::path& figures) {
  const Eigen::Index n = r.true_gain.singular_values.size();
  const std::string data = source_name("sigma.dat");
  {
    // Blocks: the plant's σ_i (index 0 … n−1), then per experiment its model's σ_i.
    std::vector<double> omega;
    for (int k = 0; k <= 120; ++k) omega.push_back(std::pow(10.0, -4.0 + 4.0 * k / 120.0));
    std::vector<Polyline> truth(static_cast<std::size_t>(n));
    std::vector<std::vector<Polyline>> models(r.experiments.size(),
                                              std::vector<Polyline>(static_cast<std::size_t>(n)));
    for (const double w : omega) {
      Eigen::JacobiSVD<Eigen::MatrixXcd> t(plant.frequency_response(w));
      for (Eigen::Index i = 0; i < n && i < t.singularValues().size(); ++i)
        truth[static_cast<std::size_t>(i)].push_back({w, t.singularValues()(i)});
      for (std::size_t e = 0; e < r.experiments.size(); ++e) {
        Eigen::JacobiSVD<Eigen::MatrixXcd> m(model_response(r.experiments[e].identified.model, w));
        const Eigen::VectorXd sv = m.singularValues();
        for (Eigen::Index i = 0; i < n && i < sv.size(); ++i) {
          models[e][static_cast<std::size_t>(i)].push_back(
              {w, std::isfinite(sv(i)) && sv(i) > 0.0 ? sv(i) : NAN});
        }
      }
    }
    std::ostringstream out;
    const PixelFrame true_frame = frame_of(truth, kSmallWidthPx, kSmallHeightPx, true, true);
    for (const Polyline& c : truth) write_block(out, simplify(c, true_frame));
    for (const auto& panel : models) {
      std::vector<Polyline> all = panel;
      all.insert(all.end(), truth.begin(), truth.end());
      const PixelFrame frame = frame_of(all, kSmallWidthPx, kSmallHeightPx, true, true);
      for (const Polyline& c : panel) write_block(out, simplify(c, frame));
    }
    write_figure_source(figures, data, out.str());
  }
  // Small multiples: one panel per design, its model's σ_i (colour) over the plant's (black).
  const auto rows = static_cast<int>((r.experiments.size() + 3) / 4);
  const std::string script = source_name("sigma.gp");
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 1150," << 240 * rows + 60
     << " dynamic font 'sans,9'\nset output " << gnuplot_string("sigma.svg")
     << "\nset multiplot layout " << rows << ",4 title "
     << gnuplot_string(
            "singular values σ_i(G(jω)): true plant (black dashed) over the model of each "
            "design (blue: directional designs, orange: the others)")
     << "\nset logscale xy\nset grid\nunset key\nset format x '10^{%L}'\nset format y "
        "'10^{%L}'\nset xlabel 'ω [rad/min]'\nset ylabel "
     << gnuplot_string(
            "σ_i " + gain_unit(common_unit_token(r.output_units), common_unit_token(r.input_units)))
     << '\n';
  const std::string file = gnuplot_string(data);
  for (std::size_t e = 0; e < r.experiments.size(); ++e) {
    const char* colour = is_directional_design(r.experiments[e].name) ? "#3060c0" : "#e08020";
    gp << "set title "
       << gnuplot_string(std::to_string(r.experiments[e].number) + " " + r.experiments[e].name)
       << "\nplot";
    for (Eigen::Index i = 0; i < n; ++i) {
      gp << (i ? ", " : " ") << file << " index " << n + static_cast<Eigen::Index>(e) * n + i
         << " with lines lw 3 lc rgb '" << colour << "'";
    }
    for (Eigen::Index i = 0; i < n; ++i)
      gp << ", " << file << " index " << i << " with lines lw 1.2 dt 2 lc rgb 'black'";
    gp << '\n';
  }
  gp << "unset multiplot\n";
  write_figure_source(figures, script, gp.str());
  return script;
}

}  // namespace

Polyline time_series_curve(const Eigen::VectorXd& v, double dt, bool hold, double width_px) {
  std::vector<double> t, y;
  for (Eigen::Index k = 0; k < v.size(); ++k) {
    t.push_back(static_cast<double>(k) * dt);
    y.push_back(v(k));
    if (hold) {
      t.push_back(static_cast<double>(k + 1) * dt);
      y.push_back(v(k));
    }
  }
  return min_max_columns(t, y, static_cast<int>(width_px));
}

bool is_directional_design(const std::string& name) {
  return name.ends_with("Dir") || name.find("Corr") != std::string::npos || name == "msGlmZipm";
}

std::string common_unit_token(const std::vector<std::string>& units) {
  if (units.empty()) return "-";
  for (const std::string& u : units) {
    if (u != units.front()) return "mixed units";
  }
  return units.front();
}

std::string common_unit(const std::vector<std::string>& units) {
  const std::string u = common_unit_token(units);
  return u == "-" ? "[–]" : "[" + u + "]";
}

std::vector<std::string> write_report_figure_scripts(const CampaignResult& r,
                                                     const sim::Plant& plant,
                                                     const std::filesystem::path& figures,
                                                     int threads) {
  std::vector<std::string> scripts(r.experiments.size());
  parallel_for(static_cast<int>(r.experiments.size()), std::max(1, threads), [&](int k) {
    const auto e = static_cast<std::size_t>(k);
    scripts[e] = plot_experiment(r.experiments[e], r, figures);
  });
  scripts.push_back(plot_projections(r, figures));
  scripts.push_back(plot_frequency(r, plant, figures));
  return scripts;
}

}  // namespace excite::host
