// SPDX-License-Identifier: MIT
// Column A, a 4080-minute identification-style experiment (both inputs change every
// minute), against a reference run of the same model at abs/rel tolerance 1e-12 computed
// in the same process. Target (issue 4 §2): max |Δx_D|, |Δx_B| ≤ 1e-8 in under 0.2 s on
// one core. For scale: GNU Octave's ode15s on the benchmark author's model needs about
// 0.4 s for 4080 minutes at that accuracy even with constant inputs.
//
//   build/default/tests/bench/sim_column/sim_column_bench
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <random>

#include "sim/column/column_plant.hpp"

namespace excite::sim::column {
namespace {

constexpr Eigen::Index kMinutes = 4080;
constexpr double kAmplitude = 0.01;  // kmol/min on L and V

Eigen::MatrixXd identification_inputs() {
  std::mt19937 rng(4080);
  std::uniform_real_distribution<double> u(-kAmplitude, kAmplitude);
  Eigen::MatrixXd in(kMinutes, 2);
  for (Eigen::Index k = 0; k < kMinutes; ++k) {
    in(k, 0) = u(rng);
    in(k, 1) = u(rng);
  }
  return in;
}

struct Reference {
  Eigen::MatrixXd inputs = identification_inputs();
  Eigen::MatrixXd outputs;
  double seconds = 0.0;
  long steps = 0;
  Reference() {
    ColumnPlant plant = ColumnPlant::cola_a();
    plant.set_tolerance({1e-12, 1e-12});
    const auto t0 = std::chrono::steady_clock::now();
    outputs = plant.simulate(inputs, 1.0);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    steps = plant.stats().accepted_steps;
    std::printf("reference (tol 1e-12): %.2f s, %ld steps, max |y| = %.3g\n", seconds, steps,
                outputs.lpNorm<Eigen::Infinity>());
  }
};

const Reference& reference() {
  static const Reference ref;
  return ref;
}

// Arg: the controller tolerance ×1e9 (100 = the plant's default, 1e-7).
void BM_ColaA_4080min_IdentificationRun(benchmark::State& state) {
  const Reference& ref = reference();
  const double tol = static_cast<double>(state.range(0)) * 1e-9;
  ColumnPlant plant = ColumnPlant::cola_a();
  plant.set_tolerance({tol, tol});
  double deviation = 0.0;
  double seconds = 0.0;
  long runs = 0;
  for (auto _ : state) {
    plant.reset();
    const auto t0 = std::chrono::steady_clock::now();
    const Eigen::MatrixXd y = plant.simulate(ref.inputs, 1.0);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    ++runs;
    deviation = (y - ref.outputs).lpNorm<Eigen::Infinity>();
    benchmark::DoNotOptimize(y.data());
  }
  state.counters["max_dev"] = deviation;
  state.counters["steps"] = static_cast<double>(plant.stats().accepted_steps);
  state.counters["rejected"] = static_cast<double>(plant.stats().rejected_steps);
  // Same process, same model: how much faster than the tight-tolerance reference run.
  state.counters["x_faster_than_ref"] = ref.seconds / (seconds / static_cast<double>(runs));
  state.SetLabel(deviation <= 1e-8 ? "within 1e-8 of reference" : "MISSES 1e-8");
  std::printf("tol %.0e: %.3f s per 4080-minute run (wall), max deviation %.3g\n", tol,
              seconds / static_cast<double>(runs), deviation);
}
BENCHMARK(BM_ColaA_4080min_IdentificationRun)
    ->Arg(100)
    ->Arg(200)
    ->Arg(300)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace excite::sim::column

BENCHMARK_MAIN();
