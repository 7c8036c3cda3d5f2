// SPDX-License-Identifier: MIT
// The modified zippered design's phases (msGlmZipm, 4.4.21) from several starts, objectives
// and a per-input polish (issue 45): the table of host/multisine/README.md, "Modified zippered:
// what was tried".
//   build/default/tests/bench/host_multisine/host_zipm_starts_bench [PLANT]   (default alatiqi4x4)
// The set is the one `excite design --preset msGlmZipm` optimises: its played amplitudes (own
// lines at c_unc/|G(0) e_j|, shared lines along v_n at c/σ_n) read back from the design's
// composition, the Schroeder start (4.4.5 per source) re-applied and the 8 high snow slots
// per channel restored. The first row must match the design's own note (printed above the
// table). Arguments other than PLANT (CTest's --benchmark_min_time) are ignored.

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <string>
#include <vector>

#include "host/design/case_studies.hpp"
#include "host/design/composition.hpp"
#include "host/design/prbs_a1.hpp"
#include "host/measures/gain_directions.hpp"
#include "host/multisine/guillaume.hpp"
#include "host/multisine/phases.hpp"
#include "host/multisine/synthesis.hpp"

namespace {

using namespace excite::host;
using namespace excite::host::multisine;

constexpr std::uint32_t kHighSnowSlots = 8;  // multisine_presets.cpp
constexpr double kSnowPowerFraction = 0.1;   // multisine_presets.cpp

double cpu_seconds() {
  return static_cast<double>(std::clock()) / CLOCKS_PER_SEC;
}

// The design's set, its phases back at the Schroeder start and its snow slots empty.
MultisineSet start_set(const Composition& comp, std::uint32_t n) {
  MultisineSet set;
  const auto lines_of = [&](const excite::signal::Source& s) {
    return std::vector<Line>(comp.lines.begin() + s.multisine.first_line,
                             comp.lines.begin() + s.multisine.first_line + s.multisine.line_count);
  };
  set.period = comp.sources.front().multisine.period;
  std::uint32_t top = 0;
  for (std::size_t k = n; k < comp.sources.size(); ++k) {
    SharedSource shared;
    shared.lines = lines_of(comp.sources[k]);
    for (std::uint32_t c = 0; c < n; ++c)
      shared.direction.push_back(comp.mix(c, static_cast<Eigen::Index>(k)));
    for (const Line& line : shared.lines) top = std::max(top, line.index);
    apply_schroeder(shared.lines);
    set.shared.push_back(shared);
  }
  const auto slots = n + static_cast<std::uint32_t>(set.shared.size());
  const std::uint32_t band_lines = top / slots;
  for (std::uint32_t c = 0; c < n; ++c) {
    std::vector<Line> own;
    for (const Line& line : lines_of(comp.sources[c]))
      if (line.index <= top) own.push_back(line);  // band; the rest is the optimiser's snow
    apply_schroeder(own);
    set.channels.push_back(own);
    std::vector<std::uint32_t> snow;
    for (std::uint32_t k = 0; k < kHighSnowSlots; ++k)
      snow.push_back(slots * (band_lines + k) + c + 1);
    set.snow.push_back(snow);
  }
  validate_set(set);
  return set;
}

struct Trial {
  const char* what;
  std::vector<StartPhases> starts;
  ChannelAggregate aggregate;
  bool polish;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string plant = argc > 1 && argv[1][0] != '-' ? argv[1] : "alatiqi4x4";
  const PriorKnowledge prior = case_study(plant);
  const PrbsDesign prbs = design_prbs(prior);
  const GainAnalysis gains = analyse_gain(prior.gain);
  const Composition comp = compose_multisine("msGlmZipm", {prior, prbs, &gains});
  for (const std::string& note : comp.notes)
    if (note.starts_with("Guillaume optimiser")) std::printf("design's note: %s\n\n", note.c_str());
  const auto n = static_cast<std::uint32_t>(prior.input_count());
  const MultisineSet start = start_set(comp, n);

  using S = StartPhases;
  const ChannelAggregate mean = ChannelAggregate::mean, worst = ChannelAggregate::worst;
  const std::vector<Trial> trials = {
      {"Schroeder per source (the design)", {S::given}, mean, false},
      {"  + per-input polish", {S::given}, mean, true},
      {"Schroeder per channel's spectrum", {S::channel_schroeder}, mean, false},
      {"Newman per source", {S::newman}, mean, false},
      {"Schroeder on the whole grid", {S::grid_schroeder}, mean, false},
      {"random, 4 seeds (best)", {S::random, S::random, S::random, S::random}, mean, false},
      {"all six starts (best)",
       {S::given, S::channel_schroeder, S::newman, S::grid_schroeder, S::random, S::random},
       mean,
       true},
      {"worst input: Schroeder per source", {S::given}, worst, false},
      {"worst input: + per-input polish", {S::given}, worst, true},
      {"worst input: Schroeder per channel", {S::channel_schroeder}, worst, false},
      {"worst input: random, 4 seeds (best)",
       {S::random, S::random, S::random, S::random},
       worst,
       false},
  };
  std::printf(
      "| start (objective: average of the inputs' CF unless 'worst input') | avg grid CF "
      "| worst | per input (continuous) | each start's avg/worst | CPU s "
      "|\n|---|---|---|---|---|---|\n");
  for (const Trial& t : trials) {
    GuillaumeOptions options;
    options.snow_power_fraction = kSnowPowerFraction;
    options.aggregate = t.aggregate;
    options.starts = t.starts;
    options.polish_own_lines = t.polish;
    GuillaumeReport report;
    const double t0 = cpu_seconds();
    const MultisineSet result = guillaume(start, options, &report);
    const double cpu = cpu_seconds() - t0;
    double avg = 0.0, top = 0.0;
    for (const double cf : report.cf_final) {
      avg += cf / static_cast<double>(report.cf_final.size());
      top = std::max(top, cf);
    }
    std::string per, starts;
    for (std::size_t c = 0; c < result.channels.size(); ++c) {
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%s%.3f", c ? " " : "",
                    cf_continuous(channel_spectrum(result, c), result.period));
      per += buffer;
    }
    for (const auto& cf : report.cf_by_start) {
      double a = 0.0, w = 0.0;
      for (const double v : cf) {
        a += v / static_cast<double>(cf.size());
        w = std::max(w, v);
      }
      char buffer[32];
      std::snprintf(buffer, sizeof buffer, "%s%.3f/%.3f", starts.empty() ? "" : ", ", a, w);
      starts += buffer;
    }
    std::printf("| %s | %.3f | %.3f | %s | %s | %.2f |\n", t.what, avg, top, per.c_str(),
                starts.c_str(), cpu);
  }
  return 0;
}
