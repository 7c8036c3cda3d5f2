// SPDX-License-Identifier: MIT
// Multisine crest-factor figures and timings (host/multisine/README.md quotes them).
//   build/default/tests/bench/host_multisine/host_multisine_bench
// Flat spectra (lines 1…N on a 256-sample period): Schroeder closed form, Guillaume with FFT
// evaluation, and the same optimiser with direct O(lines · grid) evaluation as baseline;
// the 4×4 case study (T = 1 min, τ_H = 50, τ_L = 12, α = 2, β = 3, δ = 0) zippered and
// modified zippered, every channel's crest factor as a counter. After the benchmarks, the
// baseline/FFT time ratio and the case-study designs are printed.

#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <string>

#include "../../unit/host_multisine/multisine_cases.hpp"
#include "host/multisine/allocation.hpp"
#include "host/multisine/design.hpp"
#include "host/multisine/guillaume.hpp"
#include "host/multisine/phases.hpp"
#include "host/multisine/synthesis.hpp"

namespace {

using namespace excite::host::multisine;

constexpr std::uint32_t kPeriod = 256;

using excite::host::multisine::testing::case_study_gain;  // G(0) of 6.3.1
using excite::host::multisine::testing::flat_schroeder;

DesignRequest case_study(std::uint32_t shared_slots) {
  DesignRequest request;
  request.tau_low = 12.0;
  request.tau_high = 50.0;
  request.alpha = 2.0;
  request.beta = 3.0;
  request.channels = 4;
  request.delta = 0;
  request.shared_slots = shared_slots;
  request.sample_time = 1.0;
  return request;
}

void BM_SchroederFlat(benchmark::State& state) {
  const auto count = static_cast<std::uint32_t>(state.range(0));
  double cf = 0.0;
  for (auto _ : state) {
    const auto lines = flat_schroeder(count);
    cf = cf_continuous(lines, kPeriod);
    benchmark::DoNotOptimize(cf);
  }
  state.counters["cf_continuous"] = cf;
  state.counters["cf_sampled"] = cf_sampled(flat_schroeder(count), kPeriod);
}
BENCHMARK(BM_SchroederFlat)->Arg(31)->Arg(63)->Unit(benchmark::kMicrosecond);

void guillaume_flat(benchmark::State& state, Evaluation evaluation) {
  const auto count = static_cast<std::uint32_t>(state.range(0));
  const auto start = flat_schroeder(count);
  GuillaumeOptions options;
  options.evaluation = evaluation;
  std::vector<Line> result;
  GuillaumeReport report;
  for (auto _ : state) {
    result = guillaume(start, kPeriod, options, &report);
    benchmark::DoNotOptimize(result.data());
  }
  state.counters["cf_continuous"] = cf_continuous(result, kPeriod);
  state.counters["cf_sampled"] = cf_sampled(result, kPeriod);
  state.counters["evaluations"] = report.evaluations;
  state.counters["grid"] = report.grid;
}
void BM_GuillaumeFlatFft(benchmark::State& state) {
  guillaume_flat(state, Evaluation::fft);
}
void BM_GuillaumeFlatDirect(benchmark::State& state) {
  guillaume_flat(state, Evaluation::direct);
}
BENCHMARK(BM_GuillaumeFlatFft)->Arg(31)->Arg(63)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GuillaumeFlatDirect)->Arg(31)->Arg(63)->Unit(benchmark::kMillisecond);

MultisineSet case_study_start(bool modified) {
  const auto design = design_zippered(case_study(modified ? 1 : 0));
  const ZipperedLayout layout{4, design.delta, design.lines, 0, 1.0};
  return modified ? modified_zippered_set(design.period, layout, case_study_gain(), {})
                  : zippered_set(design.period, layout);
}

void case_study_bench(benchmark::State& state, bool modified) {
  const auto start = case_study_start(modified);
  MultisineSet result;
  for (auto _ : state) {
    result = guillaume(start, {});  // the whole optimisation, all channels together
    benchmark::DoNotOptimize(result.channels.data());
  }
  for (std::size_t c = 0; c < result.channels.size(); ++c) {
    const auto lines = channel_spectrum(result, c);
    state.counters["cf_cont_" + std::to_string(c + 1)] = cf_continuous(lines, result.period);
    state.counters["cf_schroeder_" + std::to_string(c + 1)] =
        cf_continuous(channel_spectrum(start, c), start.period);
  }
  state.counters["period"] = result.period;
}
void BM_CaseStudyZippered(benchmark::State& state) {
  case_study_bench(state, false);
}
void BM_CaseStudyModifiedZippered(benchmark::State& state) {
  case_study_bench(state, true);
}
BENCHMARK(BM_CaseStudyZippered)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CaseStudyModifiedZippered)->Unit(benchmark::kMillisecond);

// CPU time of this thread in ms: the figure "on one core", unaffected by other processes
// sharing the machine.
double thread_cpu_ms() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) * 1e3 + static_cast<double>(now.tv_nsec) * 1e-6;
}

// Median thread CPU time of `repeats` calls, in ms.
template <typename Call>
double median_ms(int repeats, Call call) {
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = thread_cpu_ms();
    call();
    times.push_back(thread_cpu_ms() - t0);
  }
  std::sort(times.begin(), times.end());
  return times[times.size() / 2];
}

void print_baseline_ratio() {
  for (std::uint32_t count : {31U, 63U}) {
    const auto start = flat_schroeder(count);
    GuillaumeOptions fft;
    GuillaumeOptions direct;
    direct.evaluation = Evaluation::direct;
    const double t_fft =
        median_ms(5, [&] { benchmark::DoNotOptimize(guillaume(start, kPeriod, fft)); });
    const double t_direct =
        median_ms(3, [&] { benchmark::DoNotOptimize(guillaume(start, kPeriod, direct)); });
    std::printf(
        "N = %u: Guillaume FFT %.2f ms CPU, direct O(N·L) baseline %.2f ms CPU, ratio %.1f×\n",
        count, t_fft, t_direct, t_direct / t_fft);
  }
}

void print_case_study() {
  for (bool modified : {false, true}) {
    const auto design = design_zippered(case_study(modified ? 1 : 0));
    std::printf("\n%s design (A3), δ = 0:\n", modified ? "modified zippered" : "zippered");
    for (const auto& line : design.explanation) std::printf("  %s\n", line.c_str());
    const auto start = case_study_start(modified);
    GuillaumeReport report;
    MultisineSet result;
    const double ms = median_ms(3, [&] { result = guillaume(start, {}, &report); });
    std::printf("  optimisation %.1f ms CPU (%d evaluations, grid %u)\n", ms, report.evaluations,
                report.grid);
    for (std::size_t c = 0; c < result.channels.size(); ++c) {
      std::printf("  channel %zu: CF Schroeder %.3f → Guillaume %.3f continuous, %.3f sampled\n",
                  c + 1, cf_continuous(channel_spectrum(start, c), start.period),
                  cf_continuous(channel_spectrum(result, c), result.period),
                  cf_sampled(channel_spectrum(result, c), result.period));
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_baseline_ratio();
  print_case_study();
  return 0;
}
