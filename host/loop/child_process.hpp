// SPDX-License-Identifier: MIT
#pragma once
// A program run as a child process by the engineer's tool: excite-plant and excite-gateway
// in the loop (host/loop). stdout is a pipe the caller can read line by line; stderr goes to
// a file. The destructor stops a child still running (SIGTERM, then SIGKILL after 5 s) and
// reaps it. Errors throw std::runtime_error naming the program.

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace excite::host {

class ChildProcess {
 public:
  /// Starts `program` with `args`; its stderr goes to `stderr_file` (created or truncated).
  ChildProcess(const std::filesystem::path& program, const std::vector<std::string>& args,
               const std::filesystem::path& stderr_file);
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// The next line the child writes on stdout (without the newline), or nullopt when it
  /// closed stdout or `timeout` passed first.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout);

  /// Waits for the child to exit: its exit code, 128 + signal when a signal ended it, or
  /// nullopt when `timeout` passed first (the child keeps running).
  std::optional<int> wait(std::chrono::milliseconds timeout);

  /// Sends `signal` and waits as wait() does.
  std::optional<int> stop(int signal, std::chrono::milliseconds timeout);

  /// What the child wrote on stderr so far.
  std::string stderr_text() const;

  const std::string& name() const { return name_; }

 private:
  std::string name_;
  pid_t pid_ = -1;
  int stdout_fd_ = -1;
  std::string pending_;  // stdout read past the last returned line
  std::optional<int> exit_code_;
  std::filesystem::path stderr_file_;
};

}  // namespace excite::host
