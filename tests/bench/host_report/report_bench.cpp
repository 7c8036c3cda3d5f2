// SPDX-License-Identifier: MIT
// The case study's report, timed (issue 23 §3; issue 46: measured, never asserted): the report
// phase (index.html and its 70 figures, gnuplot on two threads) against the floor it cannot go
// below — the same number of gnuplot scripts, each an empty plot to SVG, through the same
// runner — and headless Chromium on index.html against Chromium on an empty page. Each is the
// fastest of three runs; every run is printed with wall and CPU seconds (this process's
// threads and the children it waited for: gnuplot), then the ratios. What the report must not
// do (start gnuplot per figure, load the model views eagerly, grow its figures) is asserted by
// counting in tests/integration/host_campaign/report_budget_test.cpp.
//
// Exit 0 with the figures printed; 1 when the report or Chromium fails (chromium is in
// toolchain/packages.txt: its absence is a failure, not a skip).
// usage: host_report_bench
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "../cpu_seconds.hpp"
#include "host/campaign/campaign.hpp"
#include "host/campaign/gnuplot.hpp"
#include "host/campaign/report.hpp"
#include "host/process/child_process.hpp"

namespace {

namespace fs = std::filesystem;
using excite::host::CampaignOptions;
using excite::host::CampaignResult;
using excite::host::ChildProcess;

struct Cost {
  double wall_s = 1e9;
  double cpu_s = 1e9;
};

template <class Work>
Cost timed(Work&& work) {
  const auto start = std::chrono::steady_clock::now();
  const double cpu0 = excite::bench::cpu_seconds_with_children();
  work();
  return {std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
          excite::bench::cpu_seconds_with_children() - cpu0};
}

// The fastest of three runs of `work(run)`, each printed.
template <class Work>
Cost fastest_of_three(const char* what, Work&& work) {
  Cost best;
  for (int run = 0; run < 3; ++run) {
    const Cost c = timed([&] { work(run); });
    std::printf("  %-40s run %d: wall %6.3f s  cpu %6.3f s\n", what, run + 1, c.wall_s, c.cpu_s);
    best.wall_s = std::min(best.wall_s, c.wall_s);
    best.cpu_s = std::min(best.cpu_s, c.cpu_s);
  }
  return best;
}

int count_svgs(const fs::path& folder) {
  int n = 0;
  for (const auto& entry : fs::directory_iterator(folder)) n += entry.path().extension() == ".svg";
  return n;
}

// The floor: `figures` gnuplot scripts, each an empty plot to its own SVG, run as the report
// runs its scripts (run_gnuplot_scripts: one gnuplot per thread, compacted SVGs).
void draw_empty_figures(const fs::path& folder, int figures, int threads) {
  fs::remove_all(folder);
  fs::create_directories(folder);
  excite::host::make_figure_sources(folder);
  std::vector<std::string> scripts;
  for (int k = 0; k < figures; ++k) {
    const std::string name = excite::host::source_name("empty-" + std::to_string(k) + ".gp");
    excite::host::write_figure_source(folder, name,
                                      "set terminal svg size 600,300\nset output 'empty-" +
                                          std::to_string(k) + ".svg'\nunset key\nplot [0:1] 0\n");
    scripts.push_back(name);
  }
  excite::host::run_gnuplot_scripts(folder, scripts, threads);
  excite::host::remove_figure_sources(folder);
}

// Chromium's wall time for a page: start, load it with its figures, screenshot, exit. Throws
// when Chromium fails or leaves no screenshot.
double chromium_seconds(const fs::path& page, const fs::path& profile) {
  const std::vector<std::string> args = {"--headless",
                                         "--no-sandbox",
                                         "--disable-gpu",
                                         "--disable-background-networking",
                                         "--user-data-dir=" + profile.string(),
                                         "--window-size=1400,4000",
                                         "--screenshot=" + (profile / "shot.png").string(),
                                         "file://" + page.string()};
  fs::create_directories(profile);
  fs::remove(profile / "shot.png");
  const auto start = std::chrono::steady_clock::now();
  ChildProcess chromium("chromium", args, profile / "chromium.err");
  chromium.read_all(std::chrono::minutes(5));  // its stdout, so it never blocks on the pipe
  const std::optional<int> status = chromium.wait(std::chrono::minutes(5));
  const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto shot = fs::exists(profile / "shot.png") ? fs::file_size(profile / "shot.png") : 0U;
  if (status != std::optional<int>(0) || shot < 10000U) {
    throw std::runtime_error(
        "chromium " + page.string() + ": exit status " +
        (status ? std::to_string(*status) : "none (still running)") + ", screenshot " +
        std::to_string(shot) +
        " bytes, expected 0 and at least 10000; its stderr: " + chromium.stderr_text());
  }
  return t;
}

}  // namespace

int main() try {
  const fs::path root =
      fs::temp_directory_path() / ("excite_report_bench_" + std::to_string(getpid()));
  fs::remove_all(root);
  CampaignOptions options;
  options.plant = "alatiqi4x4";
  const CampaignResult result = excite::host::run_campaign(options, {});
  const auto plant = excite::sim::make_plant("alatiqi4x4");
  constexpr int kThreads = 2;

  std::printf("report of the case study (alatiqi4x4, 17 designs), gnuplot on %d threads\n",
              kThreads);
  const Cost report = fastest_of_three("report phase", [&](int run) {
    const fs::path dir = root / ("report-" + std::to_string(run));
    fs::create_directories(dir);
    excite::host::write_report(result, *plant, dir, {}, kThreads);
  });
  const int figures = count_svgs(root / "report-0" / "figures");
  const Cost floor = fastest_of_three("floor: as many empty gnuplot figures", [&](int run) {
    draw_empty_figures(root / ("floor-" + std::to_string(run)), figures, kThreads);
  });
  std::printf("  %d figures; fastest report phase %.3f CPU s (%.3f s wall), floor %.3f CPU s\n",
              figures, report.cpu_s, report.wall_s, floor.cpu_s);
  std::printf("  ratio report / floor: cpu %.2f, wall %.2f\n", report.cpu_s / floor.cpu_s,
              report.wall_s / floor.wall_s);

  const fs::path page = root / "report-0" / "index.html";
  const fs::path blank = root / "blank.html";
  std::ofstream(blank) << "<!DOCTYPE html><html><body><p>blank</p></body></html>\n";
  const fs::path profile = root / "chromium-profile";
  chromium_seconds(blank, profile);  // a first start creates the profile: not counted
  double fastest = 1e9, fastest_blank = 1e9;
  for (int run = 0; run < 3; ++run) {
    const double b = chromium_seconds(blank, profile), t = chromium_seconds(page, profile);
    std::printf("  chromium run %d: index.html %.3f s, an empty page %.3f s\n", run + 1, t, b);
    fastest = std::min(fastest, t);
    fastest_blank = std::min(fastest_blank, b);
  }
  std::printf(
      "  chromium fastest: index.html %.3f s, an empty page %.3f s: rendering %.3f s, "
      "ratio %.2f\n",
      fastest, fastest_blank, fastest - fastest_blank, fastest / fastest_blank);
  fs::remove_all(root);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "host_report_bench: %s\n", e.what());
  return 1;
}
