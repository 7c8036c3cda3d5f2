// SPDX-License-Identifier: MIT
// Issue 28 item 4: the README runs as written. Every command of README.md's "A session with
// the tool" block is run, in order, in a scratch folder with the built binaries (`$B`), and
// its exit code is checked against what the README implies: 0, or N where its comment says
// `exits N`. A command ending in `&` runs in the background (the plant server) until the
// block is done, and must then stop cleanly on SIGTERM. What the test supplies, and only
// that: the two files the block names as the user's own (historian.csv, an export; and
// step-test.csv, an earlier run log of the same unit), the repository's `firmware/` (the
// block's paths are relative to the checkout), and a free loopback port instead of 1502, so
// parallel tests do not collide. Before: the dry-run line exited 12 where the README implied
// success.
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <thread>

#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

const fs::path kRepo = fs::path(EXCITE_LOOP_DIR) / ".." / ".." / "..";

struct Command {
  std::string line;  // as run (the comment removed)
  int expected = 0;  // `exits N` in its comment, else 0
  bool background = false;
};

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t");
  const std::size_t b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// The commands of the README's "A session with the tool" sh block.
std::vector<Command> session_commands() {
  std::ifstream in(kRepo / "README.md");
  std::ostringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const std::size_t section = all.find("## A session with the tool");
  const std::size_t open = all.find("```sh\n", section);
  const std::size_t close = all.find("\n```", open + 6);
  std::istringstream block(all.substr(open + 6, close - open - 6));
  std::vector<Command> commands;
  for (std::string line; std::getline(block, line);) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#' || t.rfind("B=", 0) == 0) continue;
    Command c;
    const std::size_t comment = line.find(" #");
    c.line = trim(comment == std::string::npos ? line : line.substr(0, comment));
    if (comment != std::string::npos) {
      const std::size_t exits = line.find("exits ", comment);
      if (exits != std::string::npos) c.expected = std::stoi(line.substr(exits + 6));
    }
    if (!c.line.empty() && c.line.back() == '&') {
      c.background = true;
      c.line = trim(c.line.substr(0, c.line.size() - 1));
    }
    commands.push_back(c);
  }
  return commands;
}

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size())) {
    s.replace(at, from.size(), to);
  }
  return s;
}

std::uint16_t free_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t n = sizeof a;
  ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &n);
  ::close(fd);
  return ntohs(a.sin_port);
}

// A historian export of one unit (FC101 → TI205, first order, gain 2, noise), 600 minutes.
void write_historian(const fs::path& file, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> noise(0.0, 0.01);
  std::ofstream out(file);
  out << "timestamp,FC101,TI205\n";
  double y = 0.0;
  double u = 0.0;
  for (int k = 0; k < 600; ++k) {
    if (k % 40 == 0) u = (random() % 2U) != 0U ? 1.0 : -1.0;
    y = 0.9 * y + 0.2 * u;
    char stamp[32];
    std::snprintf(stamp, sizeof stamp, "2026-01-01T%02d:%02d:00", k / 60, k % 60);
    out << stamp << "," << 10.0 + u << "," << 150.0 + y + noise(random) << "\n";
  }
}

class Readme : public LoopTest {};

TEST_F(Readme, EveryCommandOfTheSessionRunsWithTheExitCodeTheReadmeImplies) {
  const std::vector<Command> commands = session_commands();
  ASSERT_GE(commands.size(), 15U) << "the README's session block was not found";
  const fs::path bin = fs::path(EXCITE_TOOL).parent_path();
  ASSERT_EQ(bin, fs::path(EXCITE_GATEWAY).parent_path());

  // The user's own files, and the checkout's firmware/ where the block's paths point.
  write_historian(path("historian.csv"), 1);
  write_historian(path("earlier.csv"), 2);
  ASSERT_EQ(
      run_to_completion(EXCITE_TOOL,
                        {"import", path("earlier.csv").string(), "--mv", "FC101", "--cv", "TI205",
                         "--sample-time-min", "1", "-o", path("step-test.csv").string()},
                        path("import.out")),
      0);
  fs::create_directory_symlink(fs::canonical(kRepo / "firmware"), path("firmware"));
  const std::string port = std::to_string(free_port());

  std::vector<std::unique_ptr<PlantRunner>> background;
  int index = 0;
  for (const Command& c : commands) {
    const std::string line =
        replace_all(replace_all(c.line, "$B/", bin.string() + "/"), "1502", port);
    const fs::path out = path("command-" + std::to_string(++index) + ".out");
    if (c.background) {
      background.push_back(std::make_unique<PlantRunner>(
          "/bin/sh",
          std::vector<std::string>{"-c", "cd '" + tmp_.path().string() + "' && exec " + line},
          out));
      // The plant server says where it listens before anything else: wait for it, as a
      // user sees it before typing the next line.
      EXPECT_TRUE(background.back()->wait_listening().has_value())
          << c.line << "\n"
          << background.back()->stderr_text();
      continue;
    }
    const int rc =
        run_to_completion("/bin/sh", {"-c", "cd '" + tmp_.path().string() + "' && " + line}, out);
    std::ifstream text(out);
    std::ostringstream s;
    s << text.rdbuf();
    EXPECT_EQ(rc, c.expected) << "README: " << c.line << "\n" << s.str().substr(0, 3000);
  }
  for (auto& b : background) EXPECT_EQ(b->stop(SIGTERM).value_or(-1), 0) << b->stderr_text();
}

}  // namespace
}  // namespace excite::test
