// SPDX-License-Identifier: MIT
// Throughput of the Monte Carlo units (issue 29 §5): all 17 designs of a plant over a few
// seeds, each unit design (amortised: once per process) + simulate + identify + cross-validate
// + balance, on one thread and on two, in one process, real simulations and identification.
// Prints wall and CPU time, units per CPU second (= per core-second), the speed-up, whether
// every unit's figures are bit-identical across thread counts (exit status 1 if not), and
// apart the test-length grid's extra identifications (5 % grid) per unit.
// EXCITE_BENCH_PLANT (default woodberry2x2; alatiqi4x4 for the case study),
// EXCITE_BENCH_SEEDS (default 1).

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "host/montecarlo/records.hpp"
#include "host/montecarlo/unit.hpp"
#include "host/process/parallel.hpp"

namespace {

namespace mc = excite::host::montecarlo;

std::string env_or(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v != nullptr ? v : fallback;
}

mc::Config config(int length_step) {
  mc::Config c;
  c.plant = env_or("EXCITE_BENCH_PLANT", "woodberry2x2");
  c.seeds = std::atoi(env_or("EXCITE_BENCH_SEEDS", "1").c_str());
  c.noise_variance = 5e-4;
  c.length_step_percent = length_step;
  mc::normalise(c);
  return c;
}

struct Timing {
  double wall_s = 0.0, cpu_s = 0.0, design_cpu_s = 0.0;
  mc::UnitTimes stages;
  std::vector<std::string> units;  // each unit's file, for the bit-identity check
};

Timing run(const mc::Config& c, int threads) {
  Timing t;
  const auto t0 = std::chrono::steady_clock::now();
  const std::clock_t c0 = std::clock();
  const auto prepared = mc::prepare(c, threads);
  t.design_cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  const std::vector<mc::Unit> units = mc::all_units(c);
  std::vector<mc::UnitResult> results(units.size());
  excite::host::parallel_for(static_cast<int>(units.size()), threads, [&](int i) {
    results[static_cast<std::size_t>(i)] =
        mc::run_unit(*prepared, units[static_cast<std::size_t>(i)]);
  });
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.cpu_s = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  for (const mc::UnitResult& r : results) {
    t.stages.experiment_s += r.times.experiment_s;
    t.stages.crossval_s += r.times.crossval_s;
    t.stages.lengths_s += r.times.lengths_s;
    t.units.push_back(mc::unit_json(r).dump());
  }
  return t;
}

void BM_OneUnit(benchmark::State& state) {
  const mc::Config c = config(0);
  const auto prepared = mc::prepare(c, 1);
  for (auto _ : state) {
    const mc::UnitResult r = mc::run_unit(*prepared, {5, 1, 5});  // prbsSimDir, seed 1
    benchmark::DoNotOptimize(r.fit_avg);
  }
}
BENCHMARK(BM_OneUnit)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

int summary() {
  double load = 0.0;
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0.0;
    std::fclose(f);
  }
  const mc::Config c = config(0);
  const auto n = static_cast<double>(mc::all_units(c).size());
  std::printf("\nmontecarlo units on %s: %zu designs x %d seeds = %.0f units, load average %.1f\n",
              c.plant.c_str(), c.designs.size(), c.seeds, n, load);
  double one_wall = 0.0;
  std::vector<std::string> reference;
  bool identical = true;
  for (const int threads : {1, 2}) {
    const Timing t = run(c, threads);
    if (threads == 1) {
      one_wall = t.wall_s;
      reference = t.units;
    } else {
      identical = t.units == reference;
    }
    std::printf(
        "  threads %d: wall %.2f s, cpu %.2f s (designs %.2f, experiments %.2f, "
        "cross-validation %.2f); %.3f units per CPU second, %.3f per wall second; speed-up "
        "x%.2f\n",
        threads, t.wall_s, t.cpu_s, t.design_cpu_s, t.stages.experiment_s, t.stages.crossval_s,
        n / t.cpu_s, n / t.wall_s, one_wall / t.wall_s);
  }
  std::printf("  units bit-identical across thread counts: %s\n", identical ? "yes" : "NO");
  const Timing grid = run(config(5), 2);
  std::printf(
      "  test-length grid (5 %%, 19 prefixes identified per unit), 2 threads: %.2f CPU s in "
      "all, of which the prefixes %.2f s = %.3f CPU s per unit\n",
      grid.cpu_s, grid.stages.lengths_s, grid.stages.lengths_s / n);
  return identical ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return summary();
}
