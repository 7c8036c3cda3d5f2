// SPDX-License-Identifier: MIT
#pragma once
// The report's views of one model's quality (issue 13 §3): its step-response matrix with
// ±2σ bands from the parameter covariance against the true plant's steps, measured against
// predicted outputs, residual auto- and cross-correlation with 99 % limits, and the table of
// parameters with standard errors. Figures are gnuplot scripts written beside their data in
// the figures folder (run_gnuplot_scripts draws them as SVG).

#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// Lags of the residual correlations in the report (samples).
inline constexpr int kResidualLags = 40;

/// Unit-step responses of the true plant at t = k·T, k = 0 … samples: row k, column o·n + i.
/// Each input is stepped by 10⁻³·max(1, |baseline|) and the response divided by the step:
/// exact for the linear plants, the linearised response for the columns.
Eigen::MatrixXd true_unit_steps(sim::Plant& plant, int samples, double sample_time_min);

/// Step horizon of the report (samples): the median over the models of the time their
/// slowest element settles (host/export settling_samples), so one model with a lag on its
/// bound does not squeeze every other plot; at most the shortest experiment.
int report_step_horizon(const CampaignResult& r);

/// Writes the scripts of <name>-steps.svg, -fit.svg, -residuals.svg and their data into the
/// figures' sources (gnuplot.hpp), each curve as its panel shows it (plot_points.hpp);
/// returns the scripts' names. `truth` as true_unit_steps gives it (empty:
/// not known).
std::vector<std::string> write_model_view_scripts(const Experiment& e, const CampaignResult& r,
                                                  const Eigen::MatrixXd& truth, int horizon_samples,
                                                  const std::filesystem::path& figures);

/// The element table: CV, MV, status, K, T_d, T_p1, T_p2 each ± 1σ with units.
std::string parameter_table_html(const Experiment& e, const CampaignResult& r);

/// "y [unit]" / "[unit/unit]" helpers shared with the report: "Δy/Δu [xD unit per R unit]".
std::string gain_unit(const std::string& output_unit, const std::string& input_unit);

/// Time axis: minutes up to 600 min, hours above. {label, divisor}.
std::pair<std::string, double> time_axis(double longest_min);

/// "68 h 0 min" for long durations, "45 min" for short ones.
std::string duration_text(double minutes);

}  // namespace excite::host
