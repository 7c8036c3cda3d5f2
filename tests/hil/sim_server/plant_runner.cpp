// SPDX-License-Identifier: MIT
#include "plant_runner.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <thread>

namespace excite::test {

TempDir::TempDir() {
  std::string pattern = (std::filesystem::temp_directory_path() / "excite-plant-XXXXXX").string();
  if (mkdtemp(pattern.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
  path_ = pattern;
}

TempDir::~TempDir() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

std::filesystem::path TempDir::write(const std::string& name, const std::string& text) const {
  const std::filesystem::path file = path_ / name;
  std::ofstream(file) << text;
  return file;
}

PlantRunner::PlantRunner(const std::vector<std::string>& args, std::filesystem::path stderr_file)
    : PlantRunner(EXCITE_PLANT_PATH, args, std::move(stderr_file)) {}

PlantRunner::PlantRunner(const std::string& program_path, const std::vector<std::string>& args,
                         std::filesystem::path stderr_file)
    : stderr_file_(std::move(stderr_file)) {
  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
  const int err = open(stderr_file_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (err == -1) throw std::runtime_error("cannot open " + stderr_file_.string());
  std::vector<char*> argv;
  std::string program = program_path;
  argv.push_back(program.data());
  std::vector<std::string> copies = args;
  for (std::string& a : copies) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_ = fork();
  if (pid_ == 0) {
    dup2(out[1], STDOUT_FILENO);
    dup2(err, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out[1]);
  close(err);
  stdout_fd_ = out[0];
  if (pid_ < 0) throw std::runtime_error("fork failed");
}

PlantRunner::~PlantRunner() {
  if (pid_ > 0 && !exit_code_) {
    if (!stop(SIGTERM)) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  if (stdout_fd_ != -1) close(stdout_fd_);
}

std::optional<std::uint16_t> PlantRunner::wait_listening(std::chrono::milliseconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  std::string line;
  while (std::chrono::steady_clock::now() < end) {
    pollfd fd{stdout_fd_, POLLIN, 0};
    if (poll(&fd, 1, 20) <= 0) continue;
    char c = 0;
    if (read(stdout_fd_, &c, 1) != 1) return std::nullopt;  // exited without a line
    if (c == '\n') break;
    line += c;
  }
  first_line_ = line;
  const std::string prefix = "listening ";
  const auto colon = line.rfind(':');
  if (line.rfind(prefix, 0) != 0 || colon == std::string::npos) return std::nullopt;
  return static_cast<std::uint16_t>(std::stoi(line.substr(colon + 1)));
}

std::optional<int> PlantRunner::wait_exit(std::chrono::milliseconds timeout) {
  if (exit_code_) return exit_code_;
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (std::chrono::steady_clock::now() < end) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      return exit_code_;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return std::nullopt;
}

std::optional<int> PlantRunner::stop(int signal, std::chrono::milliseconds timeout) {
  if (exit_code_) return exit_code_;
  kill(pid_, signal);
  return wait_exit(timeout);
}

void PlantRunner::signal(int signo) const {
  if (pid_ > 0 && !exit_code_) kill(pid_, signo);
}

std::string PlantRunner::stderr_text() const {
  std::ifstream in(stderr_file_);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace excite::test

namespace excite::test {

int run_to_completion(const std::string& program, const std::vector<std::string>& args,
                      const std::filesystem::path& output_file) {
  const int out = open(output_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (out == -1) throw std::runtime_error("cannot open " + output_file.string());
  std::vector<std::string> copies = args;
  std::string program_copy = program;
  std::vector<char*> argv{program_copy.data()};
  for (std::string& a : copies) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(out, STDOUT_FILENO);
    dup2(out, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  close(out);
  if (pid < 0) throw std::runtime_error("fork failed");
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

}  // namespace excite::test
