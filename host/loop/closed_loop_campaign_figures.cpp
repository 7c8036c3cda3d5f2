// SPDX-License-Identifier: MIT
#include "host/loop/closed_loop_campaign_figures.hpp"

#include <Eigen/Core>

#include <array>
#include <sstream>
#include <stdexcept>

#include "firmware/runlog/format.hpp"
#include "firmware/runlog/reader.hpp"
#include "host/campaign/gnuplot.hpp"
#include "host/campaign/model_views.hpp"
#include "host/campaign/plot_points.hpp"
#include "host/campaign/report_figures.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/process/parallel.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

// One panel's plot area in pixels (the figure is 900 × 520, two panels).
constexpr double kWidthPx = 700.0, kHeightPx = 220.0;

// One curve of a panel: its samples, ZOH or not, dashed (r) or not, its key.
struct Curve {
  Eigen::VectorXd values;
  bool hold = false;
  bool dashed = false;
  std::string title;
};

Eigen::VectorXd column(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

// A panel: its axis label and its curves.
struct Panel {
  std::string label;
  std::vector<Curve> curves;
};

// The CVs (dy, and r on the setpoints) and the MVs (du, and r as an MV dither).
std::array<Panel, 2> panels_of(const runlog::RunLog& log) {
  std::vector<Curve> cvs, mvs;
  for (std::size_t j = 0; j < log.dy.size(); ++j)
    cvs.push_back({column(log.dy[j]), false, false, log.output_names[j]});
  for (std::size_t i = 0; i < log.du.size(); ++i)
    mvs.push_back({column(log.du[i]), true, false, log.input_names[i]});
  // r_channels: output indices (setpoint), input indices (mv), or outputs then p + input
  // index (both).
  const runlog::ClosedLoopLog& cl = log.closed_loop;
  const std::size_t p = cl.excitation == runlog::Excitation::mv ? 0 : log.dy.size();
  for (std::size_t c = 0; c < cl.r.size(); ++c) {
    const std::size_t channel = cl.r_channels[c];
    if (channel < p) {
      cvs.push_back({column(cl.r[c]), true, true, "r " + log.output_names[channel]});
    } else {
      mvs.push_back({column(cl.r[c]), true, true, "r " + log.input_names[channel - p]});
    }
  }
  return {Panel{cvs.size() > log.dy.size() ? "CVs: Δy and the setpoint offsets r" : "CVs: Δy", cvs},
          Panel{mvs.size() > log.du.size() ? "MVs: the applied Δu and the dither r"
                                           : "MVs: the applied Δu",
                mvs}};
}

// Writes the data and script of FILE.svg from `log`, titled with the design's `name`;
// returns the script's name.
std::string plot_run(const runlog::RunLog& log, const std::string& name, const std::string& file,
                     const fs::path& figures) {
  const std::array<Panel, 2> panels = panels_of(log);
  const auto [time_label, divisor] =
      time_axis(static_cast<double>(log.rows()) * log.sample_time_min);
  const double dt = log.sample_time_min / divisor;
  const std::string data = source_name(file + ".dat");
  std::ostringstream out;
  for (const Panel& panel : panels) {
    std::vector<Polyline> lines;
    for (const Curve& c : panel.curves)
      lines.push_back(time_series_curve(c.values, dt, c.hold, kWidthPx));
    const PixelFrame frame = frame_of(lines, kWidthPx, kHeightPx);
    for (const Polyline& line : lines) write_block(out, simplify(line, frame));
  }
  write_figure_source(figures, data, out.str());
  std::ostringstream gp;
  gp << "set encoding utf8\nset terminal svg size 900,520 dynamic font 'sans,11'\nset output "
     << gnuplot_string(file + ".svg") << "\nset multiplot layout 2,1 title "
     << gnuplot_string(name + " under the controller: CVs (top), MVs (bottom); r dashed")
     << "\nset xlabel " << gnuplot_string(time_label) << "\nset grid\nset key outside right\n";
  std::size_t block = 0;
  for (const Panel& panel : panels) {
    gp << "set ylabel " << gnuplot_string(panel.label) << "\nplot";
    for (std::size_t c = 0; c < panel.curves.size(); ++c, ++block) {
      const Curve& curve = panel.curves[c];
      gp << (c ? ", " : " ") << gnuplot_string(data) << " index " << block << " with lines"
         << (curve.dashed ? " dashtype 2 linewidth 2" : "") << " title "
         << gnuplot_string(curve.title);
    }
    gp << '\n';
  }
  gp << "unset multiplot\n";
  const std::string script = source_name(file + ".gp");
  write_figure_source(figures, script, gp.str());
  return script;
}

}  // namespace

std::vector<std::string> draw_closed_loop_figures(const std::vector<ClosedLoopExperiment>& runs,
                                                  const fs::path& dir, int threads) {
  const fs::path figures = dir / "figures";
  fs::create_directories(figures);
  make_figure_sources(figures);
  std::vector<std::string> scripts(runs.size()), svgs(runs.size());
  parallel_for(static_cast<int>(runs.size()), threads, [&](int k) {
    const ClosedLoopExperiment& e = runs[static_cast<std::size_t>(k)];
    const runlog::ReadResult read =
        runlog::read_run_log((dir / e.run_log).string(), limited_read_options());
    if (!read.ok()) throw std::runtime_error(read.error->to_string());
    if (!read.log.closed_loop.closed) {
      throw std::runtime_error(e.run_log + ": loop = open, expected a closed-loop run log (v4)");
    }
    const std::string file = fs::path(e.run_log).parent_path().filename().string();  // NN-name
    scripts[static_cast<std::size_t>(k)] = plot_run(read.log, e.name, file, figures);
    svgs[static_cast<std::size_t>(k)] = "figures/" + file + ".svg";
  });
  run_gnuplot_scripts(figures, scripts, threads);
  remove_figure_sources(figures);  // the report links the SVGs, the logs hold the data
  return svgs;
}

}  // namespace excite::host
