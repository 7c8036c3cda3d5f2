// SPDX-License-Identifier: MIT
// Live stepping against the batch simulation, same plant, same inputs, same process:
// sim::Plant::step (reset once, then one call per sample, as excite-plant and the
// in-process link drive it) versus sim::Plant::simulate over the whole input matrix.
// Inputs: both flows drawn uniformly in ±amplitude and changed every sample (colaA: 4080
// samples of 1 min, ±0.01 kmol/min; pilot15: 480 samples of 0.5 min, ±0.0004 kmol/min).
// items_per_second = simulated samples per second of wall time. Also printed: the most
// integrator steps (accepted + rejected) any one sample needed, against the cap.
//
//   build/default/tests/bench/sim_column/sim_column_step_bench
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "sim/column/column_plant.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim {
namespace {

struct Case {
  const char* name;
  Eigen::Index samples;
  double sample_time_min;
  double amplitude_kmol_min;
};

const Case kCases[] = {{"colaA", 4080, 1.0, 0.01}, {"pilot15", 480, 0.5, 0.0004}};

Eigen::MatrixXd inputs_of(const Case& c) {
  std::mt19937 rng(4080);
  std::uniform_real_distribution<double> u(-c.amplitude_kmol_min, c.amplitude_kmol_min);
  Eigen::MatrixXd in(c.samples, 2);
  for (Eigen::Index k = 0; k < c.samples; ++k) {
    in(k, 0) = u(rng);
    in(k, 1) = u(rng);
  }
  return in;
}

void BM_Batch(benchmark::State& state) {
  const Case& c = kCases[state.range(0)];
  const Eigen::MatrixXd u = inputs_of(c);
  auto plant = make_plant(c.name);
  for (auto _ : state) {
    const Eigen::MatrixXd y = plant->simulate(u, c.sample_time_min);
    benchmark::DoNotOptimize(y.data());
  }
  state.SetItemsProcessed(state.iterations() * c.samples);
  state.SetLabel(c.name);
}

void BM_Step(benchmark::State& state) {
  const Case& c = kCases[state.range(0)];
  const Eigen::MatrixXd u = inputs_of(c);
  auto plant = make_plant(c.name);
  double du[2];
  double dy[2];
  for (auto _ : state) {
    plant->reset(c.sample_time_min);
    for (Eigen::Index k = 0; k < c.samples; ++k) {
      du[0] = u(k, 0);
      du[1] = u(k, 1);
      plant->step(du, dy);
    }
    benchmark::DoNotOptimize(dy);
  }
  state.SetItemsProcessed(state.iterations() * c.samples);
  state.SetLabel(c.name);
}

// The work per sample, counted (ColumnPlant::step is what sim::Plant::step runs).
void print_work_per_sample() {
  for (const Case& c : kCases) {
    const Eigen::MatrixXd u = inputs_of(c);
    column::ColumnPlant plant = column::ColumnPlant::by_name(c.name);
    plant.set_sample_time_min(c.sample_time_min);
    long most = 0;
    for (Eigen::Index k = 0; k < c.samples; ++k) {
      const double in[2] = {u(k, 0), u(k, 1)};
      double out[2];
      const long before = plant.stats().accepted_steps + plant.stats().rejected_steps;
      plant.step(in, out);
      most = std::max(most, plant.stats().accepted_steps + plant.stats().rejected_steps - before);
    }
    const long total = plant.stats().accepted_steps + plant.stats().rejected_steps;
    std::printf("%s: %.2f integrator steps per sample on average, at most %ld (cap %ld)\n", c.name,
                static_cast<double>(total) / static_cast<double>(c.samples), most,
                plant.max_steps_per_sample());
  }
}

BENCHMARK(BM_Batch)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Step)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace excite::sim

int main(int argc, char** argv) {
  excite::sim::print_work_per_sample();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
