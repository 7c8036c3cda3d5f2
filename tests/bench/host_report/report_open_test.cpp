// SPDX-License-Identifier: MIT
// A report that opens (issue 23 §3), timed on the case study (alatiqi4x4, in-process):
// writing the report and its figures costs ≤ 1.5 CPU s (this process's threads and the
// gnuplot children it waited for: 1 s wall on two idle cores), and headless Chromium renders
// index.html with its figures (a screenshot) in < 2 s beyond its own start-up (the same run
// on an empty page; that difference, not Chromium's start-up, is the report's). Each is the
// fastest of three runs; every run is printed, wall time beside CPU time. The report phase
// is judged by CPU time, which another job on the machine does not inflate as it does wall
// time (a CI run measured 2.84 s wall at a 1-minute load average of 4.6 on 2 cores, more than
// the load-scaled wall budget allowed). The old report (6.8 s; Chromium 3.1 s beyond its
// start-up with the model views loaded eagerly) fails either.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <stdlib.h>  // getloadavg
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "host/campaign/campaign.hpp"
#include "host/campaign/report.hpp"
#include "host/process/child_process.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

// max(1, load average / cores): how oversubscribed the machine is right now.
double load_factor() {
  double load[1] = {0.0};
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (getloadavg(load, 1) != 1 || cores < 1) return 1.0;
  return std::max(1.0, load[0] / static_cast<double>(cores));
}

// CPU seconds (user + system) of this process's threads and of the children it has waited
// for (gnuplot).
double cpu_seconds() {
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  rusage self{};
  rusage children{};
  getrusage(RUSAGE_SELF, &self);
  getrusage(RUSAGE_CHILDREN, &children);
  return seconds(self.ru_utime) + seconds(self.ru_stime) + seconds(children.ru_utime) +
         seconds(children.ru_stime);
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

class CaseStudyReportTiming : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    CampaignOptions options;
    options.plant = "alatiqi4x4";
    result_ = new CampaignResult(run_campaign(options, {}));
    root_ = new fs::path(fs::temp_directory_path() /
                         ("excite_report_timing_" + std::to_string(getpid())));
    fs::remove_all(*root_);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*root_);
    delete result_;
    delete root_;
  }
  struct Cost {
    double wall_s = 0.0;
    double cpu_s = 0.0;
  };
  // Writes the report into root/NAME; returns its wall and CPU time.
  static Cost write(const std::string& name) {
    const fs::path dir = *root_ / name;
    fs::create_directories(dir);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = cpu_seconds();
    write_report(*result_, *sim::make_plant("alatiqi4x4"), dir, {}, 2);
    return {seconds_since(start), cpu_seconds() - cpu_start};
  }
  static CampaignResult* result_;
  static fs::path* root_;
};
CampaignResult* CaseStudyReportTiming::result_ = nullptr;
fs::path* CaseStudyReportTiming::root_ = nullptr;

TEST_F(CaseStudyReportTiming, ReportAndFiguresInAtMostOneAndAHalfCpuSeconds) {
  double fastest_cpu = 1e9;
  for (int run = 0; run < 3; ++run) {
    const Cost c = write("report-" + std::to_string(run));
    std::cout << "report phase, run " << run + 1 << ": " << c.wall_s << " s wall, " << c.cpu_s
              << " CPU s (load factor " << load_factor() << ")\n";
    fastest_cpu = std::min(fastest_cpu, c.cpu_s);
  }
  std::cout << "fastest " << fastest_cpu << " CPU s; budget 1.5 CPU s\n";
  EXPECT_LE(fastest_cpu, 1.5);
}

// `name` as posix_spawnp finds it on PATH, or empty when no executable of that name is there.
fs::path find_on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string dirs = path != nullptr ? path : "";
  std::size_t begin = 0;
  while (begin <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', begin), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(begin, end - begin)) / name;
    if (end > begin && access(candidate.c_str(), X_OK) == 0 && !fs::is_directory(candidate))
      return candidate;
    begin = end + 1;
  }
  return {};
}

// Chromium's wall time for a page: start, load index.html with its figures, screenshot, exit.
// Started with an argument vector (host/process, posix_spawnp), never through a shell.
double chromium_seconds(const fs::path& page, const fs::path& profile) {
  const std::vector<std::string> args = {"--headless",
                                         "--no-sandbox",
                                         "--disable-gpu",
                                         "--disable-background-networking",
                                         "--user-data-dir=" + profile.string(),
                                         "--window-size=1400,4000",
                                         "--screenshot=" + (profile / "shot.png").string(),
                                         "file://" + page.string()};
  std::string command = "chromium";
  for (const std::string& a : args) command += " " + a;
  fs::create_directories(profile);
  fs::remove(profile / "shot.png");
  const auto start = std::chrono::steady_clock::now();
  ChildProcess chromium("chromium", args, profile / "chromium.err");
  chromium.read_all(std::chrono::minutes(5));  // its stdout, so it never blocks on the pipe
  const std::optional<int> status = chromium.wait(std::chrono::minutes(5));
  const double t = seconds_since(start);
  EXPECT_EQ(status, std::optional<int>(0))
      << command << ": exit status " << (status ? std::to_string(*status) : "none (still running)")
      << ", expected 0; its stderr: " << chromium.stderr_text();
  EXPECT_GT(fs::exists(profile / "shot.png") ? fs::file_size(profile / "shot.png") : 0U, 10000U)
      << command;
  return t;
}

TEST_F(CaseStudyReportTiming, ChromiumRendersTheReportInUnderTwoSeconds) {
  if (find_on_path("chromium").empty()) {
    GTEST_SKIP() << "chromium not installed (toolchain/packages.txt lists it)";
  }
  write("report-browser");
  const fs::path page = *root_ / "report-browser" / "index.html";
  const fs::path blank = *root_ / "blank.html";
  { std::ofstream(blank) << "<!DOCTYPE html><html><body><p>blank</p></body></html>\n"; }
  const fs::path profile = *root_ / "chromium-profile";
  chromium_seconds(blank, profile);  // a first start creates the profile: not counted
  double fastest = 1e9, fastest_blank = 1e9;
  for (int run = 0; run < 3; ++run) {
    const double b = chromium_seconds(blank, profile), t = chromium_seconds(page, profile);
    std::cout << "chromium, run " << run + 1 << ": index.html " << t << " s, an empty page " << b
              << " s\n";
    fastest = std::min(fastest, t);
    fastest_blank = std::min(fastest_blank, b);
  }
  std::cout << "fastest: index.html " << fastest << " s, an empty page " << fastest_blank
            << " s: rendering " << fastest - fastest_blank << " s (load factor " << load_factor()
            << ")\n";
  // The same scaling as the report phase's budget: the goal is 2 s on an idle machine.
  EXPECT_LT(fastest - fastest_blank, 2.0 * load_factor());
}

}  // namespace
}  // namespace excite::host
