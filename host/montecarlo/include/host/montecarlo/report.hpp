// SPDX-License-Identifier: MIT
#pragma once
// The report of a Monte Carlo run (issue 29 §6): DIR/index.html with its figures drawn by
// gnuplot as SVG in DIR/figures/ (host/campaign/gnuplot.hpp: argument vectors, compacted
// SVG, sources removed afterwards):
//   - per metric (own fit, worst cross-fit, noise-free balance, σ_n error, v_n angle) the
//     designs' distributions over the seeds, a box (quartiles), whiskers (10–90 %) and the
//     median per design, the other designs and the directional ones grouped;
//   - the verdict by median with the share of seeds in which it holds (summary.json
//     "verdicts");
//   - T90 per design as a bar chart, and the share-vs-length curve of every design with its
//     Wilson 95 % band;
//   - the tables: spreads per design, T90, the G(0) elements biased beyond their spread.
// Made from the summary and the units only: the same run gives the same page and figures.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "host/montecarlo/unit.hpp"

namespace excite::host::montecarlo {

/// Writes DIR/index.html and DIR/figures/*.svg. `summary` is summary_json's, `units` every
/// unit of the run (all_units order). gnuplot runs on `threads` processes. Throws
/// std::runtime_error when gnuplot fails.
void write_report(const nlohmann::json& summary, const std::vector<UnitResult>& units,
                  const std::filesystem::path& dir, int threads);

}  // namespace excite::host::montecarlo
