// SPDX-License-Identifier: MIT
#pragma once
// `excite campaign --controller FILE`: what the closed-loop campaign writes beside its runs
// and models (host/loop/closed_loop_campaign.hpp): summary.json and index.html, one row per
// design (its two-stage G(0), the direct cross-check, how much of u r explains, the fits,
// the balance and the cross-validation), the plant's true G(0) above them, and each run's
// figure below (closed_loop_campaign_figures.hpp). The open-loop report (host/campaign/report.hpp)
// is another folder; the main job links the two (toolchain/dev case-study).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "host/loop/closed_loop_campaign.hpp"
#include "host/simulate/closed_loop_speed.hpp"

namespace excite::host {

struct ClosedLoopCampaignHeader {
  std::string plant;
  std::string controller;                     // the file as given
  std::string excitation;                     // setpoint | mv
  std::string directions = "none";            // setpoint: none | output (r along the prior's W)
  std::string switching = "loop";             // setpoint: (4.2.3)'s τ_L the loop's or the plant's
  double tau_low_min = 0.0;                   // the designs' τ_L
  std::optional<ClosedLoopSpeed> loop_speed;  // when τ_L is the loop's: what the loop gave
  bool loop = false;                          // through the real gateway
  std::string open_loop_report;               // a relative link to the open-loop report, or ""
  int threads = 1;                            // gnuplot processes drawing the figures
};

void write_closed_loop_summary(const ClosedLoopCampaignHeader& header,
                               const std::vector<ClosedLoopExperiment>& runs,
                               const std::filesystem::path& dir);
void write_closed_loop_report(const ClosedLoopCampaignHeader& header,
                              const std::vector<ClosedLoopExperiment>& runs,
                              const std::filesystem::path& dir);

}  // namespace excite::host
