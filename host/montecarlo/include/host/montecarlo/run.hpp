// SPDX-License-Identifier: MIT
#pragma once
// A Monte Carlo run (or one shard of it) into a folder that keeps every finished unit, so
// that an interrupted run resumes where it stopped (records.hpp for the files):
//   - DIR new or empty: DIR/run.json is written; DIR with a run.json: it must hold the same
//     configuration (else the first differing field is named); any other non-empty DIR is
//     refused.
//   - Units already in DIR are not run again; the others run on `threads` threads, each
//     written whole as soon as it finishes. A unit file that does not read back (records.hpp
//     check_unit) is removed and run again; Outcome::redone says why.
//   - One process per folder: DIR itself is locked (flock) for the whole call; a second
//     process is refused.
//   - `stop` set (e.g. by SIGINT): no new unit starts; the running ones finish and are kept.

#include <atomic>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace excite::host::montecarlo {

struct Progress {
  int done = 0;                      // units of this shard finished, earlier runs' included
  int total = 0;                     // units of this shard
  int done_before = 0;               // found finished in DIR at the start
  double elapsed_s = 0.0;            // since this run started
  double left_s = -1.0;              // estimate from this run's pace; < 0 until a unit finished
  const UnitResult* last = nullptr;  // the unit just finished (null for the first call)
};

struct Outcome {
  int total = 0, done_before = 0, done = 0;
  bool complete = false;  // every unit of the shard is in DIR
  // Where this run's time went (units run now only): process CPU seconds of the designs,
  // the units' stages summed (unit.hpp UnitTimes), and the wall time of the whole call.
  double design_cpu_s = 0.0;
  UnitTimes unit_cpu;
  double wall_s = 0.0;
  std::vector<std::string> redone;  // unit files found that did not read back: why (run again)
};

/// Runs config.shard's units into `dir` (config normalised, work.hpp). `progress` (may be
/// empty) is called once at the start and after every unit, one call at a time.
Outcome run_into(const Config& config, const std::filesystem::path& dir, int threads,
                 const std::function<void(const Progress&)>& progress,
                 const std::atomic<bool>& stop);

/// The units of `config`'s shard read from `dir`, in k order; throws std::runtime_error
/// naming the first missing unit file.
std::vector<UnitResult> read_units(const Config& config, const std::filesystem::path& dir);

}  // namespace excite::host::montecarlo
