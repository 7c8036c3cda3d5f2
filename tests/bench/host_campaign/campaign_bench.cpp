// SPDX-License-Identifier: MIT
// The whole chapter-6 campaign (17 designs simulated, identified and cross-validated) on one
// thread and on the pool (issue 14 §8), in the same process, real simulations and real
// identification. Default plant woodberry2x2 (small, 945-sample experiments);
// EXCITE_BENCH_PLANT=alatiqi4x4 runs the case study. After the benchmarks the program
// prints wall and CPU time per thread count, the speed-up against one thread, whether every
// figure is bit-identical across thread counts (exit status 1 if not), and a control: the
// speed-up of the same pool on independent arithmetic, i.e. what the machine allows now
// (on a machine shared with other jobs a process may get well under its cores).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <thread>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/process/parallel.hpp"

namespace {

using excite::host::CampaignOptions;
using excite::host::CampaignResult;

std::string plant() {
  const char* p = std::getenv("EXCITE_BENCH_PLANT");
  return p != nullptr ? p : "woodberry2x2";
}

int pool_threads() {
  return static_cast<int>(std::max(2U, std::thread::hardware_concurrency()));
}

CampaignResult run(int threads) {
  CampaignOptions options;
  options.plant = plant();
  options.threads = threads;
  return excite::host::run_campaign(options, {});
}

void BM_Campaign(benchmark::State& state) {
  for (auto _ : state) {
    const CampaignResult r = run(static_cast<int>(state.range(0)));
    benchmark::DoNotOptimize(r.crossfit.data());
  }
}
BENCHMARK(BM_Campaign)
    ->Arg(1)
    ->Arg(2)
    ->ArgName("threads")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// Every number the report prints, for the bit-identity check.
std::vector<double> figures(const CampaignResult& r) {
  std::vector<double> v(r.crossfit.data(), r.crossfit.data() + r.crossfit.size());
  for (const auto& e : r.experiments) {
    v.insert(v.end(), {e.fit_avg, e.crossfit_avg, e.balance_clean.ratio, e.balance_noisy.ratio,
                       e.balance_clean.upsilon, e.cf_avg});
    if (e.identified.gain) {
      const auto& s = e.identified.gain->singular_values;
      v.insert(v.end(), s.data(), s.data() + s.size());
    }
  }
  return v;
}

// Control: the same pool on tasks that share nothing (a spin of arithmetic each), so the
// campaign's speed-up can be read against what this machine gives the process right now.
double control_speed_up(int threads) {
  const auto spin = [](int) {
    double x = 0.0;
    for (long i = 0; i < 100'000'000; ++i) x += 1e-9 * static_cast<double>(i % 7);
    benchmark::DoNotOptimize(x);
  };
  double wall[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    excite::host::parallel_for(threads, k == 0 ? 1 : threads, spin);
    wall[k] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return wall[0] / wall[1];
}

int summary() {
  const int pool = pool_threads();
  double load = 0.0;  // the machine's 1-minute load: wall times mean little when it is high
  if (FILE* f = std::fopen("/proc/loadavg", "r")) {
    if (std::fscanf(f, "%lf", &load) != 1) load = 0.0;
    std::fclose(f);
  }
  std::printf("\ncampaign on %s, %u hardware threads, load average %.1f\n", plant().c_str(),
              std::thread::hardware_concurrency(), load);
  double one = 0.0;
  std::vector<double> reference;
  bool identical = true;
  for (const int threads : {1, pool}) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const CampaignResult r = run(threads);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    if (threads == 1) {
      one = wall;
      reference = figures(r);
    } else {
      const std::vector<double> f = figures(r);
      identical = f.size() == reference.size() &&
                  std::memcmp(f.data(), reference.data(), f.size() * sizeof(double)) == 0;
    }
    std::printf(
        "  threads %d: wall %.2f s, cpu %.2f s (%.2f cores busy), speed-up against one "
        "thread x%.2f\n",
        threads, wall, cpu, cpu / wall, one / wall);
  }
  std::printf("  results bit-identical across thread counts: %s\n", identical ? "yes" : "NO");
  std::printf(
      "  control, %d independent spins on the same pool: speed-up x%.2f (the most this "
      "machine gives now)\n",
      pool, control_speed_up(pool));
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
