// SPDX-License-Identifier: MIT
// The whole chapter-6 campaign (17 designs simulated, identified and cross-validated) on one
// thread and on the pool (issue 14 §8), in the same process, real simulations and real
// identification. Default plant woodberry2x2 (small, 945-sample experiments);
// EXCITE_BENCH_PLANT=alatiqi4x4 runs the case study. After the benchmarks the program
// prints wall time per thread count, the speed-up against one thread, and whether every
// figure is bit-identical across thread counts (exit status 1 if not).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "host/campaign/campaign.hpp"

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

int summary() {
  const int pool = pool_threads();
  std::printf("\ncampaign on %s, %u hardware threads\n", plant().c_str(),
              std::thread::hardware_concurrency());
  double one = 0.0;
  std::vector<double> reference;
  bool identical = true;
  for (const int threads : {1, pool}) {
    const auto t0 = std::chrono::steady_clock::now();
    const CampaignResult r = run(threads);
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (threads == 1) {
      one = wall;
      reference = figures(r);
    } else {
      const std::vector<double> f = figures(r);
      identical = f.size() == reference.size() &&
                  std::memcmp(f.data(), reference.data(), f.size() * sizeof(double)) == 0;
    }
    std::printf("  threads %d: wall %.2f s, speed-up against one thread x%.2f\n", threads, wall,
                one / wall);
  }
  std::printf("  results bit-identical across thread counts: %s\n", identical ? "yes" : "NO");
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
