// SPDX-License-Identifier: MIT
// Simulation throughput of the library plants (samples/s, one sample = all inputs and
// outputs at one instant), against a dense state-space baseline run in the same process.
// Run by hand for figures:  build/default/tests/bench/sim_lti/sim_lti_bench
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <functional>

#include "dense_state_space.hpp"
#include "sim/library/library.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/noise.hpp"
#include "sim/lti/sopdt.hpp"

namespace {

using excite::sim::DiscretePlant;

constexpr Eigen::Index kSamples = 100'000;

Eigen::MatrixXd binary_inputs(Eigen::Index n, Eigen::Index m) {
  Eigen::MatrixXd u(n, m);
  std::uint64_t x = 0x9E3779B97F4A7C15ULL;
  for (Eigen::Index k = 0; k < n; ++k) {
    for (Eigen::Index j = 0; j < m; ++j) {
      x ^= x << 13U;
      x ^= x >> 7U;
      x ^= x << 17U;
      u(k, j) = (x & 1U) != 0 ? 1.0 : -1.0;
    }
  }
  return u;
}

DiscretePlant alatiqi() {
  return DiscretePlant(excite::sim::library_plant("alatiqi4x4"), 1.0);
}

void BM_AlatiqiSimulate(benchmark::State& state) {
  const DiscretePlant plant = alatiqi();
  const Eigen::MatrixXd u = binary_inputs(kSamples, 4);
  for (auto _ : state) benchmark::DoNotOptimize(plant.simulate(u).data());
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlatiqiSimulate)->Unit(benchmark::kMillisecond);

void BM_AlatiqiStep(benchmark::State& state) {
  DiscretePlant plant = alatiqi();
  const Eigen::MatrixXd u = binary_inputs(kSamples, 4);
  const Eigen::MatrixXd ut = u.transpose();  // one contiguous row of inputs per sample
  double y[4];
  for (auto _ : state) {
    plant.reset();
    for (Eigen::Index k = 0; k < kSamples; ++k) {
      plant.step(ut.col(k).data(), y);
      benchmark::DoNotOptimize(y);
    }
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlatiqiStep)->Unit(benchmark::kMillisecond);

void BM_AlatiqiDenseStateSpaceBaseline(benchmark::State& state) {
  const excite::bench::DenseStateSpace dense(alatiqi());
  const Eigen::MatrixXd u = binary_inputs(kSamples / 10, 4);
  for (auto _ : state) benchmark::DoNotOptimize(dense.simulate(u).data());
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples / 10),
                                                   benchmark::Counter::kIsIterationInvariantRate);
  state.counters["states"] = static_cast<double>(dense.states());
}
BENCHMARK(BM_AlatiqiDenseStateSpaceBaseline)->Unit(benchmark::kMillisecond);

void BM_AlatiqiNoise(benchmark::State& state) {
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(kSamples, 4);
  excite::sim::MeasurementNoise noise(4, 0.03, 1);
  for (auto _ : state) {
    noise.add(y);
    benchmark::DoNotOptimize(y.data());
  }
  state.counters["samples/s"] = benchmark::Counter(static_cast<double>(kSamples),
                                                   benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_AlatiqiNoise)->Unit(benchmark::kMillisecond);

// Identification's inner loop: rebuild K e^{−sTd}/((1+sTp1)(1+sTp2)) and simulate 1000 samples.
void BM_SopdtRebuildAndSimulate1000(benchmark::State& state) {
  const Eigen::MatrixXd u = binary_inputs(1000, 1);
  std::vector<double> y(1000);
  double tau = 20.0;
  for (auto _ : state) {
    tau = tau > 40.0 ? 20.0 : tau + 0.01;
    const excite::sim::DiscreteTerm d = excite::sim::discretise_sopdt({4.49, 0.6, tau, 6.3}, 1.0);
    excite::sim::simulate_term(d, u.data(), y.data(), y.size());
    benchmark::DoNotOptimize(y.data());
  }
}
BENCHMARK(BM_SopdtRebuildAndSimulate1000)->Unit(benchmark::kMicrosecond);

void BM_SopdtDiscretiseOnly(benchmark::State& state) {
  double tau = 20.0;
  for (auto _ : state) {
    tau = tau > 40.0 ? 20.0 : tau + 0.01;
    benchmark::DoNotOptimize(excite::sim::discretise_sopdt({4.49, 0.6, tau, 6.3}, 1.0));
  }
}
BENCHMARK(BM_SopdtDiscretiseOnly)->Unit(benchmark::kMicrosecond);

// Thread CPU time in seconds (like Google Benchmark's CPU column: robust on a shared machine).
double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Best of a few timed runs, in samples per CPU second.
double rate(const std::function<void()>& run, double samples) {
  double best = 1e300;
  for (int r = 0; r < 5; ++r) {
    const double t0 = cpu_seconds();
    run();
    best = std::min(best, cpu_seconds() - t0);
  }
  return samples / best;
}

// Same-process comparison against the dense baseline, and a check that both agree.
void compare_with_baseline() {
  DiscretePlant plant = alatiqi();
  const excite::bench::DenseStateSpace dense(plant);
  const Eigen::MatrixXd u = binary_inputs(20'000, 4);
  const Eigen::MatrixXd ut = u.transpose();
  const double fast = rate([&] { benchmark::DoNotOptimize(plant.simulate(u).data()); }, 20'000);
  double y[4];
  const double stepping = rate(
      [&] {
        plant.reset();
        for (Eigen::Index k = 0; k < u.rows(); ++k) plant.step(ut.col(k).data(), y);
        benchmark::DoNotOptimize(y);
      },
      20'000);
  const double naive = rate([&] { benchmark::DoNotOptimize(dense.simulate(u).data()); }, 20'000);
  const double diff = (plant.simulate(u) - dense.simulate(u)).cwiseAbs().maxCoeff();
  std::printf(
      "alatiqi4x4 at T = 1 min (per CPU second): simulate %.2f M samples/s, step %.2f M samples/s, "
      "dense "
      "state-space baseline (%ld states) %.3f M samples/s\n"
      "  ratio simulate/baseline %.0f×, step/baseline %.0f×; max |Δy| = %.2g\n",
      fast / 1e6, stepping / 1e6, static_cast<long>(dense.states()), naive / 1e6, fast / naive,
      stepping / naive, diff);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  compare_with_baseline();
  return 0;
}
