// SPDX-License-Identifier: MIT
#pragma once
// Runs the real excite-plant executable for a test: fork/exec with the given arguments,
// stdout on a pipe (its first line, "listening HOST:PORT", gives the port), stderr to a
// file. The destructor stops a process still running (SIGTERM, then SIGKILL after 5 s).

#include <sys/types.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace excite::test {

/// A fresh directory under the system temp directory, removed with everything in it.
class TempDir {
 public:
  TempDir();
  ~TempDir();
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }
  /// Writes `text` to `name` in the directory and returns its path.
  std::filesystem::path write(const std::string& name, const std::string& text) const;

 private:
  std::filesystem::path path_;
};

class PlantRunner {
 public:
  /// Starts excite-plant with `args`; stderr goes to `stderr_file`.
  PlantRunner(const std::vector<std::string>& args, std::filesystem::path stderr_file);
  /// Starts another program the same way (the gateway, for a test of both sides).
  PlantRunner(const std::string& program_path, const std::vector<std::string>& args,
              std::filesystem::path stderr_file);
  ~PlantRunner();
  PlantRunner(const PlantRunner&) = delete;
  PlantRunner& operator=(const PlantRunner&) = delete;

  /// Waits (up to `timeout`) for the "listening HOST:PORT" line; nullopt when the process
  /// exited or printed something else first.
  std::optional<std::uint16_t> wait_listening(
      std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

  /// Sends `signal` and waits (up to `timeout`) for the exit; returns the exit code, or
  /// 128 + signal number when killed by a signal, or nullopt on timeout.
  std::optional<int> stop(int signal,
                          std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));
  /// Waits for the process to exit by itself; as stop().
  std::optional<int> wait_exit(std::chrono::milliseconds timeout = std::chrono::milliseconds(5000));

  /// Sends `signal` without waiting (SIGSTOP / SIGCONT: a stalled peer).
  void signal(int signo) const;

  /// Everything the process wrote to stderr so far.
  std::string stderr_text() const;
  /// The first stdout line, as read by wait_listening ("" if none).
  const std::string& first_line() const { return first_line_; }

 private:
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::optional<int> exit_code_;
  std::filesystem::path stderr_file_;
  std::string first_line_;
};

/// Runs `program` with `args` to its end, stdout and stderr into `output_file`; returns the
/// exit code (128 + signal when killed).
int run_to_completion(const std::string& program, const std::vector<std::string>& args,
                      const std::filesystem::path& output_file);

}  // namespace excite::test
