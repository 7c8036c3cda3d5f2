// SPDX-License-Identifier: MIT
// The main job's cost: the whole campaign (17 designs, runs, identifications,
// cross-validation) with every plan streamed through the real excite-gateway to the real
// excite-plant (`excite campaign --loop`), against the same campaign simulated in this
// process — the baseline, run in the same process just before. Prints wall and CPU seconds
// of both and their ratio.
//
// usage: host_loop_campaign_bench [PLANT] [THREADS]   (default alatiqi4x4, the cores)
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>

#include "host/campaign/campaign.hpp"
#include "host/loop/campaign_runs.hpp"
#include "../cpu_seconds.hpp"

namespace {

struct Timing {
  double wall = 0.0;
  double cpu = 0.0;
};

Timing timed(const excite::host::CampaignOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu0 = excite::bench::cpu_seconds_with_children();
  const excite::host::CampaignResult result = excite::host::run_campaign(options, {});
  Timing t;
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  t.cpu = excite::bench::cpu_seconds_with_children() - cpu0;
  if (result.experiments.size() != 17) std::abort();
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  namespace fs = std::filesystem;
  excite::host::CampaignOptions options;
  options.plant = argc > 1 ? argv[1] : "alatiqi4x4";
  options.threads = argc > 2 ? std::atoi(argv[2])
                             : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  const Timing in_process = timed(options);

  const fs::path runs =
      fs::temp_directory_path() / ("excite-loop-bench-" + std::to_string(getpid()));
  options.measured_run = excite::host::measured_runs_in_the_loop(
      options.plant, runs, {EXCITE_PLANT_SERVER, EXCITE_GATEWAY}, {});
  const Timing loop = timed(options);
  fs::remove_all(runs);

  std::printf("campaign %s, 17 designs, %d threads\n", options.plant.c_str(), options.threads);
  std::printf("  %-44s wall %7.2f s  cpu %7.2f s\n", "in-process simulation (baseline)",
              in_process.wall, in_process.cpu);
  std::printf("  %-44s wall %7.2f s  cpu %7.2f s\n", "through excite-gateway -> excite-plant",
              loop.wall, loop.cpu);
  std::printf("  ratio loop / in-process: wall %.2f, cpu %.2f\n", loop.wall / in_process.wall,
              loop.cpu / in_process.cpu);
  return 0;
}
