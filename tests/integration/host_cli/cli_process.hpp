// SPDX-License-Identifier: MIT
#pragma once
// The `excite` executable (and its sibling programs) run as processes through /bin/sh, as an
// engineer or a script would, each test in its own empty folder.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace excite_cli_test {

/// A file's bytes (empty when it cannot be read).
inline std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Whether `text` contains `part`.
inline bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

struct Result {
  int exit_code = -1;
  std::string out;  // stdout and stderr together
};

/// Runs a shell command line; stdout and stderr are captured together.
inline Result shell(const std::string& command_line) {
  const std::string command = "{ " + command_line + " ; } 2>&1";
  Result r;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    r.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

/// `excite ARGS`.
inline Result excite(const std::string& args) {
  return shell(std::string(EXCITE_CLI) + " " + args);
}

class ExciteCli : public ::testing::Test {
 protected:
  void SetUp() override {
    // The process id too: the same test run from another build tree at the same time must
    // not remove this one's folder.
    dir_ = std::filesystem::temp_directory_path() /
           ("excite_cli_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const char* name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;
};

}  // namespace excite_cli_test
