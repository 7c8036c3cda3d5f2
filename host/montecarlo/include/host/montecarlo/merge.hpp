// SPDX-License-Identifier: MIT
#pragma once
// Shards (work.hpp) put back together: the folders of shards 1 … N of one run, in any order.

#include <filesystem>
#include <vector>

#include "host/montecarlo/unit.hpp"
#include "host/montecarlo/work.hpp"

namespace excite::host::montecarlo {

struct Merged {
  Config config;                  // the run's, shard 1/1
  std::vector<UnitResult> units;  // every unit, in all_units order
};

/// Throws std::runtime_error naming the folder and what is wrong: no run.json, a
/// configuration that differs from the first folder's (the field), shards of different
/// counts, a shard given twice (both folders), shards missing (their numbers), or a shard
/// with an unfinished unit.
Merged merge_shards(const std::vector<std::filesystem::path>& dirs);

}  // namespace excite::host::montecarlo
