// SPDX-License-Identifier: MIT
// The exit-code table of firmware/app/README.md and firmware/app/exit_codes.hpp list the same
// codes with the same names (issue 10 item 7): the README is what operators read.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
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

// code → name from the README's "### Exit codes" table rows `| 12 | distorted | … |`.
std::map<int, std::string> readme_table() {
  const std::string text = slurp(EXCITE_APP_README);
  const std::size_t start = text.find("### Exit codes");
  const std::size_t end = text.find("\n### ", start + 1);
  const std::string section = text.substr(start, end - start);
  std::map<int, std::string> codes;
  const std::regex row(R"(\n\|\s*(\d+)\s*\|\s*([a-z_]+)\s*\|)");
  for (auto it = std::sregex_iterator(section.begin(), section.end(), row);
       it != std::sregex_iterator(); ++it) {
    codes[std::stoi((*it)[1])] = (*it)[2];
  }
  return codes;
}

// code → name from the enum's lines `  distorted = 12,` in exit_codes.hpp.
std::map<int, std::string> header_enum() {
  const std::string text = slurp(EXCITE_EXIT_CODES_HPP);
  std::map<int, std::string> codes;
  const std::regex entry(R"(\n\s+([a-z_]+)\s*=\s*(\d+),)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), entry);
       it != std::sregex_iterator(); ++it) {
    codes[std::stoi((*it)[2])] = (*it)[1];
  }
  return codes;
}

TEST(ExitCodes, TheReadmeTableAndTheHeaderAgree) {
  const auto readme = readme_table();
  const auto header = header_enum();
  ASSERT_GE(header.size(), 13U);
  EXPECT_EQ(readme, header);
  // The header text is the compiled enum (spot checks of both ends and the newest).
  EXPECT_EQ(static_cast<int>(ExitCode::ok), 0);
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::unconfirmed)), "unconfirmed");
  EXPECT_EQ(header.at(static_cast<int>(ExitCode::distorted)), "distorted");
  EXPECT_EQ(header.rbegin()->first, static_cast<int>(ExitCode::distorted));
}

}  // namespace
}  // namespace excite::app
