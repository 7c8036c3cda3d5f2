// SPDX-License-Identifier: MIT
// The exit-code table of firmware/app/README.md and firmware/app/exit_codes.hpp list the same
// codes with the same names (issue 10 item 7): the README is what operators read.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "firmware/app/exit_codes.hpp"

namespace excite::app {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t");
  const std::size_t b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

bool all_digits(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

// code → name from the README's "### Exit codes" table rows `| 12 | distorted | … |`.
std::map<int, std::string> readme_table() {
  const std::string text = slurp(EXCITE_APP_README);
  const std::size_t start = text.find("### Exit codes");
  const std::size_t end = text.find("\n### ", start + 1);
  std::istringstream section(text.substr(start, end - start));
  std::map<int, std::string> codes;
  for (std::string line; std::getline(section, line);) {
    if (line.rfind("|", 0) != 0) continue;
    const std::size_t bar2 = line.find('|', 1);
    const std::size_t bar3 = line.find('|', bar2 + 1);
    if (bar2 == std::string::npos || bar3 == std::string::npos) continue;
    const std::string code = trim(line.substr(1, bar2 - 1));
    if (all_digits(code)) codes[std::stoi(code)] = trim(line.substr(bar2 + 1, bar3 - bar2 - 1));
  }
  return codes;
}

// code → name from the enum's lines `  distorted = 12,` in exit_codes.hpp.
std::map<int, std::string> header_enum() {
  std::istringstream text(slurp(EXCITE_EXIT_CODES_HPP));
  std::map<int, std::string> codes;
  for (std::string line; std::getline(text, line);) {
    const std::size_t eq = line.find(" = ");
    const std::size_t comma = line.find(',', eq == std::string::npos ? 0 : eq);
    if (eq == std::string::npos || comma == std::string::npos) continue;
    const std::string name = trim(line.substr(0, eq));
    const std::string code = trim(line.substr(eq + 3, comma - eq - 3));
    if (all_digits(code) &&
        name.find_first_not_of("abcdefghijklmnopqrstuvwxyz_") == std::string::npos) {
      codes[std::stoi(code)] = name;
    }
  }
  return codes;
}

TEST(ExitCodes, TheReadmeTableAndTheHeaderAgree) {
  const auto readme = readme_table();
  const auto header = header_enum();
  ASSERT_GE(header.size(), 15U);
  EXPECT_EQ(readme, header);
  // The header text is the compiled enum (spot checks of both ends and the newest).
  EXPECT_EQ(static_cast<int>(ExitCode::ok), 0);
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::unconfirmed)), "unconfirmed");
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::distorted)), "distorted");
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::log_fault)), "log_fault");
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::device_refused)), "device_refused");
  EXPECT_EQ(header.rbegin()->first, static_cast<int>(ExitCode::device_refused));
}

}  // namespace
}  // namespace excite::app
