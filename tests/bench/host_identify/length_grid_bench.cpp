// SPDX-License-Identifier: MIT
// The Monte Carlo test-length grid's cost (issue 44 §3, §4): one design of alatiqi4x4 over
// `--seeds=S` seeds (default 20) with the 5 % grid, every unit on one thread, real
// simulations and identification (host/montecarlo run_unit). Prints, with the load average,
// the process CPU time of the units and where it went (the whole run's experiment, the
// cross-validation, the 19 prefixes of the grid), per unit. `--design=ACRONYM` (default
// prbsUnc). The baseline for warm-starting the grid: today every prefix is identified from
// scratch.

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace {

namespace mc = excite::host::montecarlo;

mc::Config config(const std::string& design, int seeds) {
  mc::Config c;
  c.plant = "alatiqi4x4";
  c.designs = {design};
  c.seeds = seeds;
  c.noise_variance = 5e-4;  // the case study's
  c.length_step_percent = 5;
  mc::normalise(c);
  return c;
}

double load_average() {
  double load = 0.0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0.0;
    std::fclose(f);
  }
  return load;
}

// One unit (seed 1) without the grid: the whole run alone, the reference for the grid's share.
void BM_UnitWithoutGrid(benchmark::State& state) {
  mc::Config c = config("prbsUnc", 1);
  c.length_step_percent = 0;
  const auto prepared = mc::prepare(c, 1);
  const mc::Unit unit = mc::all_units(c).front();
  for (auto _ : state) benchmark::DoNotOptimize(mc::run_unit(*prepared, unit).fit_avg);
}
BENCHMARK(BM_UnitWithoutGrid)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime();

}  // namespace

int main(int argc, char** argv) {
  std::string design = "prbsUnc";
  int seeds = 20;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], "--design=", 9) == 0) {
      design = argv[i] + 9;
    } else if (std::strncmp(argv[i], "--seeds=", 8) == 0) {
      seeds = std::atoi(argv[i] + 8);
    } else {
      rest.push_back(argv[i]);
    }
  }
  int rest_count = static_cast<int>(rest.size());
  benchmark::Initialize(&rest_count, rest.data());
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();

  const mc::Config c = config(design, seeds);
  const auto prepared = mc::prepare(c, 1);
  const std::vector<mc::Unit> units = mc::all_units(c);
  const std::clock_t c0 = std::clock();
  mc::UnitTimes stages;
  double fit = 0.0;
  for (const mc::Unit& u : units) {
    const mc::UnitResult r = mc::run_unit(*prepared, u);
    stages.experiment_s += r.times.experiment_s;
    stages.crossval_s += r.times.crossval_s;
    stages.lengths_s += r.times.lengths_s;
    fit += r.fit_avg / static_cast<double>(units.size());
  }
  const double cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const auto n = static_cast<double>(units.size());
  const auto prefixes = static_cast<double>(mc::length_grid(c).size() - 1);
  std::printf(
      "\nalatiqi4x4 %s x %d seeds, 5 %% grid (%.0f prefixes), one thread, load average %.1f\n"
      "  %.2f CPU s in all: per unit %.3f s, of which the whole run %.3f, cross-validation "
      "%.3f, the prefixes %.3f (%.0f %%); mean fit %.2f %%\n",
      design.c_str(), seeds, prefixes, load_average(), cpu_s, cpu_s / n, stages.experiment_s / n,
      stages.crossval_s / n, stages.lengths_s / n, 100.0 * stages.lengths_s / cpu_s, fit);
  return 0;
}
