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

/// The largest --prbs-phase: a million switching intervals, more than any test's PRBS runs.
inline constexpr std::uint32_t kMaxPrbsPhase = 1000000;

/// A run with the controller on (issue 41 §4; host/montecarlo/README.md, "With the controller
/// on"): every unit's design run closed loop in process (host/simulate/closed_loop.hpp) under
/// the controller of `controller`, identified two-stage (host/identify/closed_loop.hpp; the
/// test-length grid's prefixes too, stage 1 on the prefix alone) or direct (the output-error
/// fit on the applied u). `controller` empty: open loop.
struct ClosedLoopConfig {
  std::string controller;               // the controller file, an absolute path
  std::string excitation = "setpoint";  // or "mv" (host/campaign/closed_loop_designs.hpp)
  std::string method = "two-stage";     // or "direct": which estimate is judged
  double limit_fraction = 0.5;          // setpoint: each CV's amplitude, share of its limit
  double mv_fraction = 0.0;             // setpoint: r within this share of the MVs' room; 0: off
  std::string directions = "none";      // setpoint: "output": r along the prior's output
                                        // directions (closed_loop_designs.hpp)
  std::string switching = "loop";       // setpoint: (4.2.3)'s τ_L the loop's (at_the_loops_pace,
                                        // closed_loop_designs.hpp) or the plant's ("plant")
  // setpoint: every design's PRBS started this many switching intervals in (another
  // realisation of r: every seed of a run gets the same r; closed_loop_design.hpp)
  std::uint32_t prbs_phase = 0;
  // The controller's model perturbed per seed within ±X % (sim/library/perturb.hpp, drawn for
  // controller_model_seed(s)): a DMC built on a wrong model, as in a real plant. 0: the
  // controller file's model as it is.
  double model_perturb_percent = 0.0;
  double disturbance_std = 0.0;      // the coloured output disturbance (SimulationOptions)
  double disturbance_tau_min = 0.0;  // its time constant, > 0 when the std is
  bool on() const { return !controller.empty(); }
};

/// The seed of seed s's controller-model perturbation: another draw than the true plant's
/// (perturb.hpp seeded by s), so that with both perturbed the controller's model is not the
/// truth.
inline constexpr std::uint64_t controller_model_seed(std::uint64_t seed) {
  return seed ^ 0x636f6e74726f6c00ULL;  // "control\0"
}

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
  ClosedLoopConfig closed_loop;                   // run.json "closed_loop"; absent: open loop
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

/// Fills `designs` (empty: all 17 of Table 6.1, or closed loop every plain one; else checks
/// each name, closed loop a plain one, and puts them in Table order) and checks the rest (a
/// perturbation needs a linear library plant, so does the controller's model's, the closed
/// loop's options in range); throws std::invalid_argument naming the option, the value and
/// what was expected.
void normalise(Config& config);

}  // namespace excite::host::montecarlo
