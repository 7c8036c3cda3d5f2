// SPDX-License-Identifier: MIT
#pragma once
// What a campaign leaves in its folder: summary.json (machine-readable, one entry per
// experiment) and index.html (the report a process engineer reads), with its figures drawn
// by gnuplot as SVG in figures/.

#include <filesystem>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host {

/// The reports' style sheet (the campaign's, host/montecarlo's): one look; rows of
/// directional designs are <tr class='dir'>.
const char* report_style();

/// DIR/summary.json: [{"name","cf_avg","pips_avg","fit_avg","crossfit_avg","crossfit_best",
/// "crossfit_worst","singular_values","projection_std","ratio","upsilon", and (issue 45)
/// "truth_fit","crossfit_worst_on","truth_fit_on_worst","loss_avg","loss_worst",
/// "loss_worst_on"}…] inside {"plant", "design_gain_source", "true_singular_values",
/// "structure" ("auto" or the forced one), "truth_known", "experiments": […]}. Unknown
/// figures are null (no truth: the truth and loss fields).
void write_summary(const CampaignResult& result, const std::filesystem::path& dir);

/// What the campaign kept beside its report, per experiment (paths relative to DIR, in the
/// order of CampaignResult::experiments; empty: not kept, not linked).
struct ReportArtifacts {
  std::vector<std::string> run_logs;  // runs/NN-name/run.csv
  std::vector<std::string> models;    // models/NN-name.json
};

/// DIR/index.html and DIR/figures/*.svg: the tables, the balance and σ(G(jω)) figures, and
/// per model its quality views (model_views.hpp) with links to `artifacts`. gnuplot runs on
/// `threads` threads. Throws std::runtime_error when gnuplot fails.
void write_report(const CampaignResult& result, const sim::Plant& plant,
                  const std::filesystem::path& dir, const ReportArtifacts& artifacts = {},
                  int threads = 2);

}  // namespace excite::host
