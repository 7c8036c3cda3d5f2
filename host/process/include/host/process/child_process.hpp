// SPDX-License-Identifier: MIT
#pragma once
// A program run as a child process by the engineer's tool: excite-plant and excite-gateway
// in the loop (host/loop), gnuplot for the campaign's figures (host/campaign). Always an
// argument vector handed to posix_spawnp, never a shell, so no argument is ever parsed as a
// command. stdout is a pipe the caller can read line by line; stderr goes to a file, or into
// the same pipe. The child starts with SIGXFSZ at its default action (a file-size limit kills
// it and wait() says so, even when this process ignores the signal). The destructor stops a
// child still running (SIGTERM, then SIGKILL after 5 s) and reaps it. Errors throw
// std::runtime_error naming the program.

#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace excite::host {

class ChildProcess {
 public:
  /// Starts `program` (a path, or a name looked up in PATH) with `args`; its stderr goes to
  /// `stderr_file` (created or truncated), or into the stdout pipe when `stderr_file` is
  /// empty. It runs in `working_dir` when that is not empty.
  ChildProcess(const std::filesystem::path& program, const std::vector<std::string>& args,
               const std::filesystem::path& stderr_file,
               const std::filesystem::path& working_dir = {});
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// The next line the child writes on stdout (without the newline), or nullopt when it
  /// closed stdout or `timeout` passed first.
  std::optional<std::string> read_line(std::chrono::milliseconds timeout);

  /// Everything the child writes on stdout until it closes it or `timeout` passes (a last
  /// line without a newline included).
  std::string read_all(std::chrono::milliseconds timeout);

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
