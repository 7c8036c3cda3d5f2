// SPDX-License-Identifier: MIT
#pragma once
// A Monte Carlo run as a Slurm job array: the text of a POSIX shell script that submits
// (sbatch, script on standard input) an array of `tasks` jobs, task i running shard i/tasks
// into OUT/shard-i, and a merge job that starts when every task has succeeded
// (--dependency=afterok) and writes OUT/summary.json. A task that fails or is requeued
// resumes from its folder (run.hpp). Logs go to OUT/logs/.

#include <filesystem>
#include <string>

#include "host/montecarlo/work.hpp"

namespace excite::host::montecarlo {

struct SlurmJob {
  std::filesystem::path excite;      // the excite binary the nodes run (absolute)
  std::filesystem::path output_dir;  // OUT (absolute; on a file system the nodes share)
  int tasks = 1;                     // array size = shards (1 … 100000)
  int threads = 1;                   // per task: --threads and --cpus-per-task
};

/// `config` normalised; throws std::invalid_argument naming --slurm-tasks or --threads when
/// out of range, or a path that is not absolute.
std::string slurm_script(const Config& config, const SlurmJob& job);

/// `text` as one word for a POSIX shell (single quotes; a ' inside as '\'').
std::string shell_word(const std::string& text);

}  // namespace excite::host::montecarlo
