// SPDX-License-Identifier: MIT
#include "host/montecarlo/merge.hpp"

#include <map>
#include <stdexcept>
#include <string>

#include "host/montecarlo/records.hpp"
#include "host/montecarlo/run.hpp"

namespace excite::host::montecarlo {
namespace fs = std::filesystem;

Merged merge_shards(const std::vector<fs::path>& dirs) {
  if (dirs.empty())
    throw std::runtime_error("merge: no folder given, expected the shards' folders");
  std::vector<Config> configs;
  for (const fs::path& dir : dirs) {
    if (!fs::exists(dir / "run.json")) {
      throw std::runtime_error(dir.string() +
                               ": no run.json, expected the folder of an excite montecarlo shard");
    }
    configs.push_back(read_config(dir / "run.json"));
  }
  const Config& first = configs.front();
  std::map<int, std::size_t> by_index;
  for (std::size_t i = 0; i < configs.size(); ++i) {
    const std::string difference = first_difference(configs[i], first);
    if (!difference.empty()) {
      throw std::runtime_error(dirs[i].string() + "/run.json: " + difference + " (as in " +
                               dirs.front().string() + "), expected shards of one run");
    }
    if (configs[i].shard.count != first.shard.count) {
      throw std::runtime_error(
          dirs[i].string() + "/run.json: shard = " + std::to_string(configs[i].shard.index) + "/" +
          std::to_string(configs[i].shard.count) + ", expected one of " +
          std::to_string(first.shard.count) + " (as in " + dirs.front().string() + ")");
    }
    const auto [it, inserted] = by_index.emplace(configs[i].shard.index, i);
    if (!inserted) {
      throw std::runtime_error("shard " + std::to_string(configs[i].shard.index) + "/" +
                               std::to_string(first.shard.count) +
                               " given twice: " + dirs[it->second].string() + " and " +
                               dirs[i].string() + ", expected each shard once");
    }
  }
  std::string missing;
  for (int s = 1; s <= first.shard.count; ++s) {
    if (by_index.count(s) == 0)
      missing += (missing.empty() ? "" : ", ") + std::to_string(s) + "/" +
                 std::to_string(first.shard.count);
  }
  if (!missing.empty()) {
    throw std::runtime_error("shard " + missing + " missing, expected all " +
                             std::to_string(first.shard.count) + " shards of the run");
  }
  Merged merged;
  merged.config = first;
  merged.config.shard = {};
  std::map<long long, UnitResult> by_number;
  for (const auto& [index, i] : by_index) {
    std::vector<UnitResult> units = read_units(configs[i], dirs[i]);
    const std::vector<Unit> slots = shard_units(configs[i]);
    for (std::size_t k = 0; k < slots.size(); ++k)
      by_number.emplace(slots[k].number, std::move(units[k]));
  }
  for (auto& [number, unit] : by_number) merged.units.push_back(std::move(unit));
  return merged;
}

}  // namespace excite::host::montecarlo
