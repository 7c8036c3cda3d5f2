// SPDX-License-Identifier: MIT
#pragma once
// The report's campaign-wide figures (issue 5, issue 23 §3): every experiment's inputs and
// outputs over time, the noise-free output projections (5.5.2) and σ_i(G(jω)) of every
// model against the plant. Each is a gnuplot script with its data in the figures' sources
// folder (gnuplot.hpp); the curves hold what their panels can show (plot_points.hpp), and
// the dense projection clouds are raster images inside the SVG, axes and text vector.

#include <filesystem>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/campaign/plot_points.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// Whether a Table 6.1 design uses gain directions (shaded rows, blue curves).
bool is_directional_design(const std::string& name);

/// "[unit]" when every channel has the same unit, "[–]" when dimensionless, else
/// "[mixed units]"; common_unit_token without the brackets ("-" when dimensionless).
std::string common_unit_token(const std::vector<std::string>& units);
std::string common_unit(const std::vector<std::string>& units);

/// A column of samples over time as the curve a time-series panel `width_px` wide shows:
/// min/max per pixel column (plot_points.hpp). `hold`: the samples are held for one sample
/// time dt (inputs, zero-order hold), drawn as the staircase they are.
Polyline time_series_curve(const Eigen::VectorXd& v, double dt, bool hold, double width_px);

/// Writes the scripts and data of <name>.svg per experiment, projections.svg and sigma.svg;
/// returns the scripts' names relative to `figures`. The experiments' figures are prepared on
/// `threads` threads.
std::vector<std::string> write_report_figure_scripts(const CampaignResult& r,
                                                     const sim::Plant& plant,
                                                     const std::filesystem::path& figures,
                                                     int threads);

}  // namespace excite::host
