// SPDX-License-Identifier: MIT
#include "host/montecarlo/run.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <mutex>
#include <stdexcept>

#include "host/montecarlo/records.hpp"
#include "host/output/whole_file.hpp"
#include "host/process/parallel.hpp"
#include "sim/plants/plant.hpp"

namespace excite::host::montecarlo {
namespace fs = std::filesystem;

namespace {

void claim_folder(const Config& config, const fs::path& dir) {
  const fs::path run_file = dir / "run.json";
  if (fs::exists(run_file)) {
    const Config found = read_config(run_file);
    std::string difference = first_difference(found, config);
    if (difference.empty() &&
        (found.shard.index != config.shard.index || found.shard.count != config.shard.count)) {
      difference = "shard = " + std::to_string(found.shard.index) + "/" +
                   std::to_string(found.shard.count) + ", expected " +
                   std::to_string(config.shard.index) + "/" + std::to_string(config.shard.count);
    }
    if (!difference.empty()) {
      throw std::runtime_error(run_file.string() + ": " + difference +
                               " (this command's); resume with the same options or use "
                               "another folder");
    }
    return;
  }
  if (fs::exists(dir) && !fs::is_directory(dir))
    throw std::runtime_error(dir.string() + ": not a folder, expected a new or empty folder");
  if (fs::exists(dir) && !fs::is_empty(dir)) {
    throw std::runtime_error(dir.string() +
                             ": a folder with files and no run.json, expected a new or empty "
                             "folder or a Monte Carlo run's");
  }
  fs::create_directories(dir);
  write_whole_file(run_file, config_json(config).dump(2) + "\n");
}

// One process per folder: an exclusive flock on the folder itself, held until the call
// returns or the process ends (two resumes of one folder once ran the same units twice,
// racing on their files). A lock on the folder leaves no file behind.
class FolderLock {
 public:
  explicit FolderLock(const fs::path& dir) {
    fd_ = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd_ < 0) {
      throw std::runtime_error(dir.string() + ": cannot be opened (" + std::strerror(errno) +
                               "), expected a folder excite can lock");
    }
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      throw std::runtime_error(dir.string() +
                               ": locked = by another process, expected one excite montecarlo "
                               "per folder (wait for it, or end it: what finished is kept)");
    }
  }
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;
  ~FolderLock() { ::close(fd_); }

 private:
  int fd_ = -1;
};

}  // namespace

Outcome run_into(const Config& config, const fs::path& dir, int threads,
                 const std::function<void(const Progress&)>& progress,
                 const std::atomic<bool>& stop) {
  if (threads < 1)
    throw std::invalid_argument("--threads = " + std::to_string(threads) + ", expected >= 1");
  claim_folder(config, dir);
  const FolderLock one_process(dir);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Unit> units = shard_units(config);
  const std::unique_ptr<sim::Plant> plant = sim::make_plant(config.plant);
  std::vector<Unit> pending;
  Outcome outcome;
  for (const Unit& u : units) {
    const fs::path file = unit_path(dir, config, u);
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(file, ec))) {
      pending.push_back(u);
      continue;
    }
    // A unit file that does not read back (cut short by a copy, a full disk elsewhere) is run
    // again, said, not counted as done: it once blocked every resume without a hint.
    try {
      check_unit(read_unit(file), config, u, plant->outputs(), plant->inputs(), file);
    } catch (const std::exception& e) {
      outcome.redone.emplace_back(e.what());
      fs::remove(file, ec);
      pending.push_back(u);
    }
  }
  outcome.total = static_cast<int>(units.size());
  outcome.done_before = outcome.total - static_cast<int>(pending.size());
  outcome.done = outcome.done_before;
  std::mutex mutex;
  Progress state;
  state.total = outcome.total;
  state.done = state.done_before = outcome.done_before;
  if (progress) progress(state);
  if (!pending.empty() && !stop) {
    const std::clock_t design_start = std::clock();
    const std::unique_ptr<Prepared> prepared = prepare(config, threads);
    outcome.design_cpu_s = static_cast<double>(std::clock() - design_start) / CLOCKS_PER_SEC;
    parallel_for(static_cast<int>(pending.size()), threads, [&](int i) {
      if (stop) return;
      const Unit& unit = pending[static_cast<std::size_t>(i)];
      const UnitResult result = run_unit(*prepared, unit);
      const fs::path file = unit_path(dir, config, unit);
      fs::create_directories(file.parent_path());
      write_whole_file(file, unit_json(result).dump(1) + "\n");
      const std::lock_guard<std::mutex> lock(mutex);
      ++outcome.done;
      outcome.unit_cpu.experiment_s += result.times.experiment_s;
      outcome.unit_cpu.crossval_s += result.times.crossval_s;
      outcome.unit_cpu.lengths_s += result.times.lengths_s;
      state.done = outcome.done;
      state.elapsed_s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const int this_run = state.done - state.done_before;
      state.left_s = state.elapsed_s / this_run * (state.total - state.done);
      state.last = &result;
      if (progress) progress(state);
      state.last = nullptr;
    });
  }
  outcome.complete = outcome.done == outcome.total;
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return outcome;
}

std::vector<UnitResult> read_units(const Config& config, const fs::path& dir) {
  const std::unique_ptr<sim::Plant> plant = sim::make_plant(config.plant);
  std::vector<UnitResult> out;
  for (const Unit& u : shard_units(config)) {
    const fs::path file = unit_path(dir, config, u);
    if (!fs::exists(file)) {
      throw std::runtime_error(
          dir.string() + ": unit " + config.designs[static_cast<std::size_t>(u.design)] + " seed " +
          std::to_string(u.seed) + " missing (" + file.string() +
          "), expected every unit of shard " + std::to_string(config.shard.index) + "/" +
          std::to_string(config.shard.count) + "; rerun it to finish");
    }
    UnitResult r = read_unit(file);
    check_unit(r, config, u, plant->outputs(), plant->inputs(), file);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace excite::host::montecarlo
