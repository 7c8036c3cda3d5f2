// SPDX-License-Identifier: MIT
#pragma once
// What a Monte Carlo run is asked to do, and how the work is cut into units and shards.
// A unit is one (design, seed) pair; units are numbered design-major,
//   k = d · seeds + (s − first_seed), d the design's index in `designs`,
// and shard i of N (1-based) runs the units with k mod N = i − 1: a deterministic slice,
// the same whatever the thread count, with every design spread over the shards.

#include <cstdint>
#include <string>
#include <vector>

namespace excite::host::montecarlo {

struct Shard {
  int index = 1;  // 1 … count
  int count = 1;
};

/// "i/N" → Shard; throws std::invalid_argument naming `--shard`, the value and the form
/// expected (1 ≤ i ≤ N ≤ 100000).
Shard parse_shard(const std::string& text);

/// A run's options: everything that decides its results (written to DIR/run.json; a rerun
/// into the same folder must give the same, and merged shards must agree on all but the
/// shard index).
/// How the test-length grid's prefixes are identified (unit.hpp, evaluate_length_grid): each
/// from scratch (cold, the default), or from the previous length's model (warm, `excite
/// montecarlo --warm-grid`: not yet the default, some verdicts differ; README).
enum class GridStart { warm, cold };

struct Config {
  std::string plant;
  std::vector<std::string> designs;  // Table 6.1 acronyms, in Table order, no repeats
  int seeds = 0;                     // ≥ 1
  std::uint64_t first_seed = 1;      // seeds first_seed … first_seed + seeds − 1
  double noise_variance = 0.0;       // per output (resolved: the case study's by default)
  int length_step_percent = 5;   // the test-length grid: step, 2·step, …, 100 %; 0: 100 % only
  double perturb_percent = 0.0;  // the true plant's parameters within ±X % per seed (perturb.hpp)
  Shard shard;
  GridStart length_grid_start = GridStart::cold;  // run.json "length_grid_start"; absent: cold
                                                  // (the runs before the warm grid)
};

/// Noise seed of experiment `number` (Table 6.1) in Monte Carlo seed s: 100·s + number —
/// what `excite campaign --seed 100s` gives that experiment, so one seed can be rerun whole.
inline constexpr std::uint64_t kSeedStride = 100;

struct Unit {
  int design = 0;          // index into Config::designs
  std::uint64_t seed = 0;  // Monte Carlo seed
  long long number = 0;    // k above
};

/// Every unit of the run (all shards), in k order.
std::vector<Unit> all_units(const Config& config);
/// The units of config.shard, in k order.
std::vector<Unit> shard_units(const Config& config);

/// The grid of the test-length evaluation in percent of the run, ascending, ending at 100.
std::vector<int> length_grid(const Config& config);

/// Fills `designs` (empty: all 17 of Table 6.1; else checks each name and puts them in Table
/// order) and checks the rest (a perturbation needs a linear library plant); throws
/// std::invalid_argument naming the option, the value and what was expected.
void normalise(Config& config);

}  // namespace excite::host::montecarlo
