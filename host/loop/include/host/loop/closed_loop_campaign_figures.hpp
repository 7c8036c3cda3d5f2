// SPDX-License-Identifier: MIT
#pragma once
// The closed-loop report's figures: per run, what the controller did with r, drawn from the
// run log the report links (DIR/runs/NN-name/run.csv). Top panel: the CVs' dy and, for a
// setpoint excitation, the setpoint offsets r (dashed); bottom panel: the applied MV moves
// du and, for an MV dither, r. gnuplot scripts and data as the open-loop report writes them
// (host/campaign/gnuplot.hpp), the curves reduced to what a panel shows (plot_points.hpp).

#include <filesystem>
#include <string>
#include <vector>

#include "host/loop/closed_loop_campaign.hpp"

namespace excite::host {

/// Draws DIR/figures/NN-name.svg for every run, `threads` gnuplot processes at a time, and
/// returns their paths relative to DIR in run order. Throws std::runtime_error naming the
/// run log when it cannot be read or is not a closed-loop log, and what run_gnuplot_scripts
/// throws.
std::vector<std::string> draw_closed_loop_figures(const std::vector<ClosedLoopExperiment>& runs,
                                                  const std::filesystem::path& dir, int threads);

}  // namespace excite::host
