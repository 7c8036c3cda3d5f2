// SPDX-License-Identifier: MIT
// Table generation of the SPEC §4 case-study shapes (4 channels × 4080 samples) by the
// signal core, against naive baselines in the same process; prints the ratios.
//   (a) 4 shifted PRBS, n_r = 8, hold 16, dense 4×4 mix
//   (b) 4 multisines of 60 lines on a 4080-sample period, dense 4×4 mix
//   (c) 4 step sequences (sequential ±a steps of 330 samples), dense 4×4 mix
// Counter `allocs`: heap allocations per iteration in the timed loop (the core's must be 0).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "../../unit/signal/example_recipes.hpp"
#include "counting_new.hpp"
#include "firmware/signal/generate.hpp"
#include "firmware/signal/mseq.hpp"

namespace excite::signal {
namespace {

using namespace excite::signal::testing;  // NOLINT: recipe builders

constexpr std::uint32_t kChannels = 4;
constexpr std::uint32_t kSamples = 4080;

std::unique_ptr<Recipe> prbs_recipe() {
  auto r = empty_recipe(kChannels, kSamples);
  for (std::uint32_t j = 0; j < 4; ++j) add_prbs(*r, 8, 1.0, 16, 16 * j);
  set_dense_mix(*r);
  return r;
}

std::unique_ptr<Recipe> multisine_recipe() {
  auto r = empty_recipe(kChannels, kSamples);
  for (std::uint32_t j = 0; j < 4; ++j) add_random_multisine(*r, kSamples, 60, 10 + j);
  set_dense_mix(*r);
  return r;
}

std::unique_ptr<Recipe> steps_recipe() {
  auto r = empty_recipe(kChannels, kSamples);
  for (std::uint32_t j = 0; j < 4; ++j) add_steps(*r, 660 * j, 660, {{1.0, 330}, {-1.0, 330}});
  set_dense_mix(*r);
  return r;
}

// Naive baselines: the textbook formula per sample (libm cos per line and sample for the
// multisine, a linear search of the segments for steps), allocating their intermediates.
// `bits`: the source's m-sequence, one period (PRBS sources only).
double naive_source(const Recipe& r, const Source& s, const std::vector<bool>& bits,
                    std::uint32_t k) {
  if (k < s.start || k >= s.start + s.length) return 0.0;
  const std::uint32_t t = k - s.start;
  switch (s.kind) {
    case SourceKind::steps: {
      std::uint32_t end = 0;
      for (std::uint32_t g = 0; g < s.steps.segment_count; ++g) {
        end += s.steps.segments[g].length;
        if (t < end) return s.steps.segments[g].level;
      }
      return 0.0;
    }
    case SourceKind::prbs: {
      const bool bit = bits[(s.prbs.shift + t / s.prbs.hold_samples) % bits.size()];
      return bit ? s.prbs.amplitude : -s.prbs.amplitude;
    }
    case SourceKind::multisine: {
      double sum = 0.0;
      for (std::uint32_t l = 0; l < s.multisine.line_count; ++l) {
        const Line& line = r.lines[s.multisine.first_line + l];
        sum += line.amplitude *
               std::cos(2.0 * std::numbers::pi * line.index * t / s.multisine.period + line.phase);
      }
      return sum;
    }
    default:
      return 0.0;
  }
}

void naive_generate(const Recipe& r, std::vector<double>& table) {
  // Every PRBS source's m-sequence tabulated once per table, then looked up per sample.
  std::vector<std::vector<bool>> bits(r.source_count);
  for (std::uint32_t i = 0; i < r.source_count; ++i) {
    if (r.sources[i].kind != SourceKind::prbs) continue;
    MSequence seq(r.sources[i].prbs.register_length);
    bits[i].resize(seq.period());
    for (std::size_t b = 0; b < bits[i].size(); ++b) bits[i][b] = seq.next();
  }
  std::vector<double> s(r.source_count);
  for (std::uint32_t k = 0; k < r.samples; ++k) {
    for (std::uint32_t i = 0; i < r.source_count; ++i) {
      s[i] = naive_source(r, r.sources[i], bits[i], k);
    }
    for (std::uint32_t c = 0; c < r.channels; ++c) {
      double v = 0.0;
      for (std::uint32_t i = 0; i < r.source_count; ++i) v += r.mix[c][i] * s[i];
      table[std::size_t{k} * r.channels + c] = v;
    }
  }
}

void run_core(benchmark::State& state, const Recipe& recipe) {
  std::vector<double> table(std::size_t{kChannels} * kSamples);
  std::vector<double> scratch(scratch_size(recipe));
  const long before = excite::test::allocations();
  for (auto _ : state) {
    const Status status = generate(recipe, {table.data(), kChannels, kSamples}, scratch);
    if (!status) state.SkipWithError(status.message());
    benchmark::DoNotOptimize(table.data());
    benchmark::ClobberMemory();
  }
  state.counters["allocs"] =
      benchmark::Counter(static_cast<double>(excite::test::allocations() - before),
                         benchmark::Counter::kAvgIterations);
  state.SetItemsProcessed(state.iterations() * kSamples);
}

void run_naive(benchmark::State& state, const Recipe& recipe) {
  std::vector<double> table(std::size_t{kChannels} * kSamples);
  const long before = excite::test::allocations();
  for (auto _ : state) {
    naive_generate(recipe, table);
    benchmark::DoNotOptimize(table.data());
    benchmark::ClobberMemory();
  }
  state.counters["allocs"] =
      benchmark::Counter(static_cast<double>(excite::test::allocations() - before),
                         benchmark::Counter::kAvgIterations);
  state.SetItemsProcessed(state.iterations() * kSamples);
}

void BM_a_Prbs_Core(benchmark::State& s) {
  run_core(s, *prbs_recipe());
}
void BM_a_Prbs_Naive(benchmark::State& s) {
  run_naive(s, *prbs_recipe());
}
void BM_b_Multisine_Core(benchmark::State& s) {
  run_core(s, *multisine_recipe());
}
void BM_b_Multisine_Naive(benchmark::State& s) {
  run_naive(s, *multisine_recipe());
}
void BM_c_Steps_Core(benchmark::State& s) {
  run_core(s, *steps_recipe());
}
void BM_c_Steps_Naive(benchmark::State& s) {
  run_naive(s, *steps_recipe());
}

BENCHMARK(BM_a_Prbs_Core)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_a_Prbs_Naive)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_b_Multisine_Core)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_b_Multisine_Naive)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_c_Steps_Core)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_c_Steps_Naive)->Unit(benchmark::kMicrosecond);

// Console output as usual, plus the CPU time per iteration of every run, for the ratios
// (CPU time: the machine is shared, wall time is noisy).
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    ConsoleReporter::ReportRuns(runs);
    for (const Run& run : runs) {
      if (!run.error_occurred) times_[run.run_name.str()] = run.GetAdjustedCPUTime();
    }
  }
  void print_ratios() const {
    for (const char* name : {"a_Prbs", "b_Multisine", "c_Steps"}) {
      const auto core = times_.find(std::string("BM_") + name + "_Core");
      const auto naive = times_.find(std::string("BM_") + name + "_Naive");
      if (core == times_.end() || naive == times_.end() || core->second <= 0.0) continue;
      std::printf("ratio naive/core %-12s %8.1f x\n", name, naive->second / core->second);
    }
  }

 private:
  std::map<std::string, double> times_;
};

}  // namespace
}  // namespace excite::signal

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  excite::signal::RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  benchmark::Shutdown();
  return 0;
}
