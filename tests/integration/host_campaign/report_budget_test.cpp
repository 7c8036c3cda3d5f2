// SPDX-License-Identifier: MIT
// The case study's report is one people can open (issue 23 §3): for the 4×4 case study
// (alatiqi4x4, as `excite campaign --plant alatiqi4x4` runs it in-process) figures/ holds at
// most 10 MB, no figure is larger than 300 KB, only the figures stay (their gnuplot sources
// are gone), and every figure the page names exists. Timing (report phase ≤ 1 s, Chromium
// < 2 s) is measured in tests/bench/host_report.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "host/campaign/campaign.hpp"
#include "host/campaign/report.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;

TEST(CaseStudyReport, FiguresFitTenMegabytesNoneAbove300KilobytesAndOnlyFiguresStay) {
  CampaignOptions options;
  options.plant = "alatiqi4x4";
  const CampaignResult result = run_campaign(options, {});
  const fs::path dir =
      fs::temp_directory_path() / ("excite_report_budget_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  write_report(result, *sim::make_plant("alatiqi4x4"), dir, {}, 2);

  std::uintmax_t total = 0, largest = 0;
  std::string largest_name;
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "figures")) {
    ASSERT_TRUE(entry.is_regular_file()) << entry.path();  // no sources folder left
    EXPECT_EQ(entry.path().extension(), ".svg") << entry.path();
    const std::uintmax_t size = entry.file_size();
    total += size;
    ++files;
    if (size > largest) largest = size, largest_name = entry.path().filename().string();
  }
  std::cout << "figures/: " << files << " files, " << total << " bytes; largest " << largest_name
            << " " << largest << " bytes\n";
  EXPECT_LE(total, 10'000'000U);
  EXPECT_LE(largest, 300'000U) << largest_name;
  EXPECT_EQ(files, 3 * 17 + 17 + 2);

  std::ifstream in(dir / "index.html");
  const std::string html{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  // Every src='figures/…' the page names exists (a plain scan: std::regex trips GCC 12's
  // -Wmaybe-uninitialized under the asan preset's -O1 and sanitizers).
  int named = 0;
  const std::string marker = "src='figures/";
  for (std::size_t at = html.find(marker); at != std::string::npos; at = html.find(marker, at)) {
    const std::size_t begin = at + 5;  // after "src='"
    const std::size_t end = html.find('\'', begin);
    ASSERT_NE(end, std::string::npos);
    const std::string name = html.substr(begin, end - begin);
    EXPECT_TRUE(fs::exists(dir / name)) << name;
    ++named;
    at = end;
  }
  EXPECT_GE(named, files);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace excite::host
