// SPDX-License-Identifier: MIT
// The Monte Carlo test-length grid cold against warm (issue 44, "The length grid
// warm-started"): one design of a plant over `--seeds=S` seeds (default 20) with the 5 % grid,
// every seed's experiment run once (host/campaign run_experiment, as run_unit does) and its
// 19 prefixes identified twice in the same process: cold (every prefix from scratch, as before
// the warm grid; `excite montecarlo`, the default) and warm (each from the previous length's
// model, checked against the cold fit until it settles, polished only where the added rows
// bring nothing new: unit.hpp, evaluate_length_grid). Real simulations and
// identification, one thread.
//
// Prints, with the load average: wall and thread-CPU time of the experiments and of each
// grid, their ratio, the units' cost either way; where the grid's work went (prefixes
// identified, fitted both ways before the warm chain settled, from the previous length alone,
// only polished; Levenberg–Marquardt iterations of all rows); the
// share meeting the criterion per length and T90 cold and warm; and every (seed, length)
// whose verdict differs, with both fits' BIC summed over the rows (row_criterion of
// host/identify) so the better one is named. Exit status 1 when a verdict differs and the
// warm fit is not the better one (the warm grid would have changed an answer for the worse).
// `--design=ACRONYM` (default prbsUnc), `--plant=NAME` (default alatiqi4x4). CTest runs it
// with 2 seeds (the figures: by hand, 20).

#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/montecarlo/summary.hpp"
#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace {

namespace mc = excite::host::montecarlo;
namespace host = excite::host;

double load_average() {
  double load = 0.0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0.0;
    std::fclose(f);
  }
  return load;
}

double wall_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

int lm_iterations(const mc::GridEvaluation& g) {
  int n = 0;
  for (const auto& r : g.results)
    if (r)
      for (const host::OutputFit& f : r->fits) n += f.iterations;
  return n;
}

struct Totals {
  double wall = 0.0, cpu = 0.0;
  int identified = 0, warm = 0, polished = 0, checked = 0, warm_better = 0, iterations = 0;
  std::vector<int> met;  // per grid length
};

}  // namespace

int main(int argc, char** argv) {
  std::string design = "prbsUnc";
  std::string plant = "alatiqi4x4";
  int seeds = 20;
  for (int i = 1; i < argc; ++i) {
    if (std::strncmp(argv[i], "--design=", 9) == 0) {
      design = argv[i] + 9;
    } else if (std::strncmp(argv[i], "--plant=", 8) == 0) {
      plant = argv[i] + 8;
    } else if (std::strncmp(argv[i], "--seeds=", 8) == 0) {
      seeds = std::atoi(argv[i] + 8);
    } else if (std::strncmp(argv[i], "--benchmark", 11) == 0) {
      // ctest's --benchmark_min_time (excite_add_bench): no Google Benchmark case here.
    } else {
      std::fprintf(stderr, "unknown argument %s, expected --design=, --plant= or --seeds=\n",
                   argv[i]);
      return 2;
    }
  }
  mc::Config c;
  c.plant = plant;
  c.designs = {design};
  c.seeds = seeds;
  c.noise_variance = 5e-4;  // the case study's
  c.length_step_percent = 5;
  mc::normalise(c);
  const auto prepared = mc::prepare(c, 1);
  const std::vector<int> grid = mc::length_grid(c);

  Totals cold, warm;
  cold.met.assign(grid.size(), 0);
  warm.met.assign(grid.size(), 0);
  double experiment_wall = 0.0, experiment_cpu = 0.0;
  int differing = 0, differing_warm_worse = 0;
  for (const mc::Unit& u : mc::all_units(c)) {
    host::CampaignOptions options = prepared->campaign;
    options.seed = mc::kSeedStride * u.seed;
    const double w0 = wall_s(), c0 = mc::thread_cpu_s();
    const host::Experiment e =
        host::run_experiment(prepared->designs[0], prepared->presets[0], options, c.noise_variance,
                             prepared->truth.gain, prepared->max_time_constant_min);
    experiment_wall += wall_s() - w0;
    experiment_cpu += mc::thread_cpu_s() - c0;
    mc::GridEvaluation evaluated[2];
    Totals* totals[2] = {&cold, &warm};
    const mc::GridStart modes[2] = {mc::GridStart::cold, mc::GridStart::warm};
    for (int m = 0; m < 2; ++m) {
      const double w1 = wall_s(), c1 = mc::thread_cpu_s();
      evaluated[m] = mc::evaluate_length_grid(*prepared, prepared->truth, e, grid, modes[m]);
      totals[m]->wall += wall_s() - w1;
      totals[m]->cpu += mc::thread_cpu_s() - c1;
      totals[m]->identified += evaluated[m].identified;
      totals[m]->warm += evaluated[m].warm;
      totals[m]->polished += evaluated[m].polished;
      totals[m]->checked += evaluated[m].checked;
      totals[m]->warm_better += evaluated[m].warm_better;
      totals[m]->iterations += lm_iterations(evaluated[m]);
      for (std::size_t k = 0; k < grid.size(); ++k)
        totals[m]->met[k] += evaluated[m].points[k].met ? 1 : 0;
    }
    for (std::size_t k = 0; k + 1 < grid.size(); ++k) {
      if (evaluated[0].points[k].met == evaluated[1].points[k].met) continue;
      ++differing;
      const auto rows = static_cast<Eigen::Index>(evaluated[0].points[k].samples);
      const double bic_cold = mc::prefix_bic(*evaluated[0].results[k], e.Y.topRows(rows));
      const double bic_warm = mc::prefix_bic(*evaluated[1].results[k], e.Y.topRows(rows));
      if (!(bic_warm < bic_cold)) ++differing_warm_worse;
      std::printf(
          "  verdict differs: seed %llu, %d %% (%lld rows): cold %s, warm %s; BIC over the rows "
          "cold %.3f, warm %.3f (%s better)\n",
          static_cast<unsigned long long>(u.seed), grid[k],
          static_cast<long long>(evaluated[0].points[k].samples),
          evaluated[0].points[k].met ? "met" : "not met",
          evaluated[1].points[k].met ? "met" : "not met", bic_cold, bic_warm,
          bic_warm < bic_cold ? "warm" : "cold");
    }
  }

  const auto n = static_cast<double>(seeds);
  std::printf("\n%s %s x %d seeds, %zu-point grid (5 %%), one thread, load average %.1f\n",
              plant.c_str(), design.c_str(), seeds, grid.size(), load_average());
  std::printf("  experiments (whole run: simulate, identify, balance): wall %.2f s, CPU %.2f s\n",
              experiment_wall, experiment_cpu);
  for (const auto& [name, t] : {std::pair{"cold", &cold}, std::pair{"warm", &warm}}) {
    std::printf(
        "  grid %s: wall %.2f s, CPU %.2f s (%.3f CPU s per unit); %d prefixes identified: %d "
        "fitted cold and warm (warm kept, the lower BIC, in %d), %d from the previous length "
        "alone, %d of them only polished; %d LM iterations; unit with its experiment %.3f CPU "
        "s\n",
        name, t->wall, t->cpu, t->cpu / n, t->identified, t->checked, t->warm_better, t->warm,
        t->polished, t->iterations, (experiment_cpu + t->cpu) / n);
  }
  std::printf("  ratio cold / warm: grid wall x%.2f, grid CPU x%.2f, unit CPU x%.2f\n",
              cold.wall / warm.wall, cold.cpu / warm.cpu,
              (experiment_cpu + cold.cpu) / (experiment_cpu + warm.cpu));
  std::vector<double> share_cold, share_warm;
  std::printf("  share meeting the criterion, percent: cold / warm\n   ");
  for (std::size_t k = 0; k < grid.size(); ++k) {
    share_cold.push_back(cold.met[k] / n);
    share_warm.push_back(warm.met[k] / n);
    std::printf(" %d:%d/%d", grid[k], cold.met[k], warm.met[k]);
  }
  const auto t90 = [&](const std::vector<double>& s) {
    const auto k = mc::t90_index(s);
    return k ? std::to_string(grid[*k]) + " %" : std::string("none");
  };
  std::printf("\n  T90 cold %s, warm %s; verdicts differing %d of %zu (warm the worse fit in %d)\n",
              t90(share_cold).c_str(), t90(share_warm).c_str(), differing,
              (grid.size() - 1) * static_cast<std::size_t>(seeds), differing_warm_worse);
  return differing_warm_worse > 0 ? 1 : 0;
}
