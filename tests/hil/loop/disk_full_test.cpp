// SPDX-License-Identifier: MIT
// Issue 19 item 2, with the real gateway and the real plant server over a real socket: a full
// disk or a file-size limit never takes control away.
//  - the gateway's run log on a small tmpfs the test mounts itself, filled mid-run: the
//    gateway stops the excitation, ramps out with verified writes and confirms the baseline
//    (the plant's own log shows the ramp and the baseline), exits 13 naming ENOSPC, and its
//    log reads back whole (before: the run went on to the end and exited 7, the log cut);
//  - `ulimit -f` (prlimit --fsize) on the gateway: the same with EFBIG (before: killed by
//    SIGXFSZ, no ramp-out, the last row cut mid-row);
//  - `ulimit -f` on excite-plant: it keeps serving, the gateway completes, the plant's log is
//    whole up to its last full row and its exit code says logging failed (before: killed by
//    SIGXFSZ mid-run, the gateway lost its peer);
//  - `--log /dev/full`: refused before any excitation with the reason (before: "cannot write
//    the run log's header: ok").
#include <fcntl.h>
#include <sys/mount.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

std::size_t data_rows(const fs::path& csv) {
  std::ifstream in(csv);
  std::size_t rows = 0;
  for (std::string line; std::getline(in, line);) rows += line.empty() || line[0] == '#' ? 0U : 1U;
  return rows == 0 ? 0 : rows - 1;  // the column row
}

// The file ends on a complete row: its last byte is a newline.
bool ends_on_a_row(const fs::path& csv) {
  const std::string text = slurp(csv);
  return !text.empty() && text.back() == '\n';
}

// The plant's own log: every input back at its baseline at the end, and the way there a ramp
// (rows strictly between the excitation and the baseline) after row `from`.
void expect_ramp_out_to_baseline(const runlog::RunLog& plant, std::size_t from) {
  ASSERT_GT(plant.rows(), from + 2);
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    const std::vector<double>& du = plant.du[i];
    EXPECT_LE(std::abs(du.back()), 1e-6 * (1 + std::abs(plant.u[i].back())))
        << plant.input_names[i] << " is not back at its baseline";
    double excited = 0.0;
    for (std::size_t k = 0; k < from; ++k) excited = std::max(excited, std::abs(du[k]));
    std::size_t between = 0;
    for (std::size_t k = from; k < du.size(); ++k) {
      if (std::abs(du[k]) > 1e-6 && std::abs(du[k]) < excited - 1e-6) ++between;
    }
    EXPECT_GT(excited, 0.01) << plant.input_names[i] << " was never excited";
    EXPECT_GE(between, 3U) << plant.input_names[i] << ": no ramp-out after row " << from;
  }
}

// A tmpfs of `size` mounted on `dir` for the test's life (root or CAP_SYS_ADMIN).
class SmallDisk {
 public:
  SmallDisk(const fs::path& dir, const std::string& size) : dir_(dir) {
    fs::create_directories(dir);
    const std::string options = "size=" + size + ",mode=0777";
    if (::mount("excite-test", dir.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, options.c_str()) == 0) {
      mounted_ = true;
    } else {
      error_ = std::strerror(errno);
    }
  }
  ~SmallDisk() {
    if (mounted_) ::umount2(dir_.c_str(), MNT_DETACH);
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  bool mounted() const { return mounted_; }
  const std::string& error() const { return error_; }

  /// Takes every free byte with a file of its own; returns the bytes taken.
  std::size_t fill() const {
    const int fd = ::open((dir_ / "filler").c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    if (fd < 0) return 0;
    std::vector<char> chunk(64 * 1024, 'x');
    std::size_t taken = 0;
    for (std::size_t size = chunk.size(); size > 0; size /= 2) {
      while (true) {
        const ssize_t n = ::write(fd, chunk.data(), size);
        if (n <= 0) break;
        taken += static_cast<std::size_t>(n);
      }
    }
    ::close(fd);
    return taken;
  }

 private:
  fs::path dir_;
  bool mounted_ = false;
  std::string error_;
};

class DiskFull : public LoopTest {
 protected:
  void start(const std::vector<std::string>& plant_args = {"--clock", "lockstep"}) {
    port_ = start_loop(kPlant, "--input-range 2 --period-s 0.01", plant_args);
    plan_ = design(kPlant, "prbsUnc");
    // A ramp of 30 ticks, so the way back to the baseline is visible on the plant's side.
    edit_gateway("comm_fail_limit = 3", "comm_fail_limit = 3\nramp_s = 0.3");
  }

  void edit_gateway(const std::string& from, const std::string& to) {
    const fs::path p = path("gateway.toml");
    std::string text = slurp(p);
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(p) << text;
  }

  bool wait_for_rows(const fs::path& csv, std::size_t rows, std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      if (data_rows(csv) > rows) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }

  /// The gateway (argument vector as start_gateway's) under `prlimit --fsize=BYTES`.
  std::unique_ptr<GatewayProcess> start_gateway_limited(const fs::path& log, long bytes) {
    return std::make_unique<GatewayProcess>(
        kPrlimit,
        std::vector<std::string>{"--fsize=" + std::to_string(bytes), EXCITE_GATEWAY, "--config",
                                 path("gateway.toml").string(), "--plan", plan_.string(), "--log",
                                 log.string(), "--start"},
        path("gw").string());
  }

  fs::path plan_;
  std::uint16_t port_ = 0;
};

// GIVEN the gateway's run log on a 512 KiB tmpfs, streaming to excite-plant (its log
// elsewhere)
// WHEN the disk fills up mid-run (another file takes every free byte)
// THEN the gateway stops the excitation, ramps out and confirms the baseline: the plant's own
//      log ramps back to the baseline; exit 13 naming ENOSPC; its run log reads back whole.
TEST_F(DiskFull, AFullDiskMidRunRampsOutToTheBaselineAndExits13) {
  SmallDisk disk(path("small"), "512k");
  if (!disk.mounted()) {
    GTEST_SKIP() << "cannot mount a tmpfs on " << path("small")
                 << " (needs root or CAP_SYS_ADMIN): " << disk.error();
  }
  start();
  const fs::path log = path("small") / "gw.csv";
  auto gw = std::make_unique<GatewayProcess>(
      EXCITE_GATEWAY,
      std::vector<std::string>{"--config", path("gateway.toml").string(), "--plan", plan_.string(),
                               "--log", log.string(), "--start"},
      path("gw").string());
  ASSERT_TRUE(wait_for_rows(log, 200, 30s)) << gw->err();  // 2 s: past the ramp-in
  ASSERT_GT(disk.fill(), 0U);
  const std::size_t plant_rows_at_fill = data_rows(path("plant.csv"));
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 13) << err;
  EXPECT_NE(err.find("No space left on device (ENOSPC)"), std::string::npos) << err;
  EXPECT_NE(err.find("the log is whole up to its last full row"), std::string::npos) << err;
  EXPECT_NE(err.find("fault: the run log could not be written"), std::string::npos) << err;
  EXPECT_NE(err.find("-> aborted"), std::string::npos) << err;
  EXPECT_NE(err.find("excite-gateway: safe after"), std::string::npos) << err;

  // The run log reads back whole, up to a row before the end of the plan.
  EXPECT_TRUE(ends_on_a_row(log));
  const runlog::RunLog written = read_log_or_fail(log);
  EXPECT_GE(written.rows(), 200U);
  EXPECT_LT(written.rows(), 900U) << "the run went on after the disk was full";

  const runlog::RunLog plant = stop_plant_and_read_its_log();
  expect_ramp_out_to_baseline(plant, plant_rows_at_fill);
}

// GIVEN the gateway under `ulimit -f 20` (prlimit --fsize=20480)
// THEN it is not killed by SIGXFSZ: the write beyond the limit fails (EFBIG), the excitation
//      ramps out to a confirmed baseline, exit 13, and its log is whole and within the limit.
TEST_F(DiskFull, TheGatewayUnderAFileSizeLimitRampsOutAndExits13) {
  if (access(kPrlimit, X_OK) != 0) GTEST_SKIP() << kPrlimit << " not found (util-linux)";
  start();
  auto gw = start_gateway_limited(path("gw.csv"), kSizeLimit);
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 13) << err;
  EXPECT_NE(err.find("File too large (EFBIG)"), std::string::npos) << err;
  EXPECT_NE(err.find("excite-gateway: safe after"), std::string::npos) << err;
  EXPECT_LE(static_cast<long>(fs::file_size(path("gw.csv"))), kSizeLimit);
  EXPECT_TRUE(ends_on_a_row(path("gw.csv")));
  const runlog::RunLog written = read_log_or_fail(path("gw.csv"));
  EXPECT_GT(written.rows(), 50U);
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  expect_ramp_out_to_baseline(plant, written.rows());
}

// GIVEN excite-plant under `ulimit -f 20`, the gateway streaming the whole plan to it
// THEN the plant keeps serving (the gateway completes, exit 0), its log is whole up to its
//      last full row, and SIGTERM ends it with exit 3 saying why.
TEST_F(DiskFull, ThePlantUnderAFileSizeLimitKeepsServingAndSaysWhy) {
  if (access(kPrlimit, X_OK) != 0) GTEST_SKIP() << kPrlimit << " not found (util-linux)";
  loop_config(kPlant, 1502, "--input-range 2 --period-s 0.005");
  plant_ = std::make_unique<PlantRunner>(
      kPrlimit,
      std::vector<std::string>{"--fsize=" + std::to_string(kSizeLimit), EXCITE_PLANT, "--config",
                               path("plant.toml").string(), "--modbus-tcp", "127.0.0.1:0", "--log",
                               path("plant.csv").string(), "--clock", "lockstep"},
      path("plant.stderr"));
  const auto port = plant_->wait_listening();
  ASSERT_TRUE(port.has_value()) << plant_->stderr_text();
  loop_config(kPlant, *port, "--input-range 2 --period-s 0.005");
  plan_ = design(kPlant, "prbsUnc");
  auto gw = start_gateway(plan_, {"--start", "--clock", "lockstep"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err() << plant_->stderr_text();
  const auto plant_rc = plant_->stop(SIGTERM);
  const std::string err = plant_->stderr_text();
  EXPECT_EQ(plant_rc.value_or(-1), 3) << err;
  EXPECT_NE(err.find("File too large (EFBIG); logging stopped, the log is whole up to its last "
                     "full row"),
            std::string::npos)
      << err;
  EXPECT_LE(static_cast<long>(fs::file_size(path("plant.csv"))), kSizeLimit);
  EXPECT_TRUE(ends_on_a_row(path("plant.csv")));
  const runlog::RunLog plant = read_log_or_fail(path("plant.csv"));
  // "cannot write sample N": the log holds samples 0 … N−1.
  const std::size_t at = err.find("cannot write sample ");
  ASSERT_NE(at, std::string::npos) << err;
  EXPECT_EQ(plant.rows(), std::stoul(err.substr(at + 20)));
}

// Issue 28 item 1: a size limit of the gateway's own (gateway.log_max_mb, default 1024 MB), so
// a run suspended for hours cannot fill a disk: reached, it is a log fault like a full disk.
TEST_F(DiskFull, ARunLogAtItsSizeLimitRampsOutAndExits13) {
  start();
  edit_gateway("comm_fail_limit = 3", "comm_fail_limit = 3\nlog_max_mb = 0.02");
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 13) << err;
  EXPECT_NE(err.find("it would pass gateway.log_max_mb = 0.02 MB (20000 bytes)"), std::string::npos)
      << err;
  EXPECT_LE(fs::file_size(path("gw.csv")), 20000U);
  EXPECT_TRUE(ends_on_a_row(path("gw.csv")));
  const runlog::RunLog written = read_log_or_fail(path("gw.csv"));
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  expect_ramp_out_to_baseline(plant, written.rows());
}

// `--log /dev/full`: the header cannot be written; refused before any excitation, exit 7,
// naming the reason (before: "cannot write the run log's header: ok").
TEST_F(DiskFull, ALogThatCannotTakeItsHeaderIsRefusedWithTheReason) {
  start();
  auto gw = std::make_unique<GatewayProcess>(
      EXCITE_GATEWAY,
      std::vector<std::string>{"--config", path("gateway.toml").string(), "--plan", plan_.string(),
                               "--log", "/dev/full", "--start"},
      path("gw").string());
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 7) << gw->err();
  EXPECT_NE(gw->err().find("/dev/full: cannot write the run log's header: No space left on "
                           "device (ENOSPC)"),
            std::string::npos)
      << gw->err();
  // Nothing was excited: the plant took at most the one sample of the baseline written at
  // arm (too short for the log reader), and its inputs there are the baseline (du = 0).
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0) << plant_->stderr_text();
  std::ifstream in(path("plant.csv"));
  std::size_t rows = 0;
  bool header_seen = false;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (!header_seen) {
      header_seen = true;  // t_min,k,du_u1,du_u2,u_u1,…
      continue;
    }
    ++rows;
    std::istringstream cells(line);
    std::vector<std::string> cell;
    for (std::string c; std::getline(cells, c, ',');) cell.push_back(c);
    ASSERT_GE(cell.size(), 4U) << line;
    EXPECT_EQ(std::stod(cell[2]), 0.0) << line;
    EXPECT_EQ(std::stod(cell[3]), 0.0) << line;
  }
  EXPECT_LE(rows, 1U);
}

}  // namespace
}  // namespace excite::test
