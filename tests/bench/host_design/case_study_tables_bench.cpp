// SPDX-License-Identifier: MIT
// Generating the tables of the 17 case-study designs (4 channels; 4080 samples for steps and
// PRBS, whole multisine periods for the others: 3770, 4713 or 4 × 3770) with the firmware
// signal core, as the gateway does at start-up; allocations during generation
// are counted (they must be 0) and the total is compared with a naive generator in the
// same process that evaluates every source sample by sample through std::vector rows.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <vector>

#include "counting_new.hpp"
#include "firmware/signal/generate.hpp"
#include "firmware/signal/mseq.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/presets.hpp"

namespace {

using excite::host::Design;

const std::vector<Design>& designs() {
  static const std::vector<Design> all = [] {
    std::vector<Design> d;
    const auto prior = excite::host::case_study("alatiqi4x4");
    for (const auto& preset : excite::host::presets())
      d.push_back(excite::host::design_preset(prior, preset, 0));
    return d;
  }();
  return all;
}

// The signal core: every design's table into preallocated storage.
void BM_SignalCoreAllEightDesigns(benchmark::State& state) {
  const auto& all = designs();
  std::size_t values = 0, scratch_values = 0;
  double samples = 0.0;
  for (const Design& d : all) {
    values = std::max<std::size_t>(values, std::size_t{d.plan->recipe.samples} * 4);
    scratch_values = std::max(scratch_values, excite::signal::scratch_size(d.plan->recipe));
    samples += d.plan->recipe.samples;
  }
  std::vector<double> table(values);
  std::vector<double> scratch(scratch_values);
  long allocations = 0;
  for (auto _ : state) {
    const long before = excite::test::allocations();
    for (const Design& d : all) {
      const auto& r = d.plan->recipe;
      const excite::signal::Status s =
          excite::signal::generate(r, {table.data(), r.channels, r.samples}, scratch);
      if (!s) state.SkipWithError(s.message());
      benchmark::DoNotOptimize(table.data());
    }
    allocations += excite::test::allocations() - before;
  }
  state.counters["allocations"] = static_cast<double>(allocations);
  state.counters["samples/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * samples, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SignalCoreAllEightDesigns)->Unit(benchmark::kMicrosecond);

// Naive baseline: per sample, per source, regenerate the PRBS bit from the m-sequence
// start and push rows into vectors (what a first implementation might do).
void BM_NaiveAllEightDesigns(benchmark::State& state) {
  const auto& all = designs();
  double samples = 0.0;
  for (const Design& d : all) samples += d.plan->recipe.samples;
  for (auto _ : state) {
    for (const Design& d : all) {
      const auto& r = d.plan->recipe;
      std::vector<std::vector<double>> rows;
      for (std::uint32_t k = 0; k < r.samples; ++k) {
        std::vector<double> row(r.channels, 0.0);
        for (std::uint32_t i = 0; i < r.source_count; ++i) {
          const auto& s = r.sources[i];
          if (k < s.start || k >= s.start + s.length) continue;
          const std::uint32_t t = k - s.start;
          double v = 0.0;
          if (s.kind == excite::signal::SourceKind::prbs) {
            excite::signal::MSequence seq(s.prbs.register_length);
            const std::uint32_t bit = (t / s.prbs.hold_samples + s.prbs.shift) % seq.period();
            bool b = false;
            for (std::uint32_t j = 0; j <= bit; ++j) b = seq.next();
            v = b ? s.prbs.amplitude : -s.prbs.amplitude;
          } else if (s.kind == excite::signal::SourceKind::steps) {
            std::uint32_t at = 0;
            for (std::uint32_t g = 0; g < s.steps.segment_count; ++g) {
              if (t >= at && t < at + s.steps.segments[g].length) v = s.steps.segments[g].level;
              at += s.steps.segments[g].length;
            }
          }
          for (std::uint32_t c = 0; c < r.channels; ++c) row[c] += r.mix[c][i] * v;
        }
        rows.push_back(std::move(row));
      }
      benchmark::DoNotOptimize(rows.data());
    }
  }
  state.counters["samples/s"] = benchmark::Counter(
      static_cast<double>(state.iterations()) * samples, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_NaiveAllEightDesigns)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
