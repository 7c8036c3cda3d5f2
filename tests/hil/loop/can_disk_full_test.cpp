// SPDX-License-Identifier: MIT
// Issue 20 with issue 19's guarantee: excite-plant --can logs through the same run-log path as
// over Modbus (sim/server/plant_log.hpp), so a full disk or a file-size limit never stops it
// serving. The real gateway streams a whole plan over vcan0 (label can-vm: run in
// toolchain/can-vm's VM) to the real plant whose log cannot grow:
//  - under `ulimit -f 20` (prlimit --fsize=20480): EFBIG, not killed by SIGXFSZ;
//  - on an 8-page tmpfs the test mounts (root in the VM): ENOSPC;
// in both the gateway completes (exit 0: its peer kept answering), the plant's log is whole
// up to its last full row, and SIGTERM ends the plant with exit 3 saying why.
#include <sys/mount.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "can_loop_fixture.hpp"
#include "loop_facts.hpp"

namespace excite::test {
namespace {

class CanDiskFull : public CanLoop {
 protected:
  // Streams woodberry2x2's prbsUnc plan (≈ 950 rows) in lock-step to the plant started by
  // start_can_loop; expects the plant to have logged part of it, then stops the plant and
  // checks what it said and left: `error` named, exit 3, the log whole up to the sample named.
  void stream_and_check(const fs::path& log, const std::string& error) {
    const fs::path plan = design("woodberry2x2", "prbsUnc");
    auto gw = start_gateway(plan, {"--start", "--clock", "lockstep"});
    const auto rc = gw->wait(60s);
    ASSERT_TRUE(rc.has_value()) << gw->err();
    EXPECT_EQ(*rc, 0) << gw->err() << plant_->stderr_text();
    const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
    const auto plant_rc = plant_->stop(SIGTERM);
    const std::string err = plant_->stderr_text();
    EXPECT_EQ(plant_rc.value_or(-1), 3) << err;
    EXPECT_NE(err.find(error + "; logging stopped, the log is whole up to its last full row"),
              std::string::npos)
        << err;
    // Said at once and again at the stop, after the summary.
    const std::size_t first = err.find("cannot write sample ");
    ASSERT_NE(first, std::string::npos) << err;
    EXPECT_NE(err.find("cannot write sample ", first + 1), std::string::npos) << err;
    EXPECT_LT(err.find("frames of other identifiers"), err.rfind("cannot write sample ")) << err;
    // Serving went on: one plant sample per gateway row, all of them.
    EXPECT_NE(err.find("stopped after " + std::to_string(gwl.rows()) + " samples"),
              std::string::npos)
        << err;
    const std::string text = slurp(log);
    ASSERT_FALSE(text.empty());
    EXPECT_EQ(text.back(), '\n') << "the log ends mid-row";
    const runlog::RunLog plant = read_log_or_fail(log);
    const std::size_t logged = std::stoul(err.substr(first + 20));
    EXPECT_EQ(plant.rows(), logged) << "\"cannot write sample N\": samples 0 … N−1 logged";
    EXPECT_GT(logged, 20U);
    EXPECT_LT(logged, gwl.rows()) << "the limit was never reached";
    for (std::size_t k = 0; k < plant.rows(); ++k) {
      ASSERT_EQ(static_cast<float>(plant.u[0][k]), static_cast<float>(gwl.u[0][k])) << "row " << k;
    }
  }
};

// GIVEN excite-plant --can under `ulimit -f 20`; WHEN the gateway streams a whole plan to it
// THEN the plant is not killed by SIGXFSZ, keeps serving to the end, and exits 3 naming EFBIG.
TEST_F(CanDiskFull, ThePlantUnderAFileSizeLimitKeepsServingAndSaysWhy) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  ASSERT_EQ(access(kPrlimit, X_OK), 0) << kPrlimit << " not found (util-linux; the VM has it)";
  start_can_loop("woodberry2x2", "--input-range 2 --period-s 0.005", {"--clock", "lockstep"}, kBus,
                 {kPrlimit, "--fsize=" + std::to_string(kSizeLimit), EXCITE_PLANT});
  stream_and_check(path("plant.csv"), "File too large (EFBIG)");
  EXPECT_LE(static_cast<long>(fs::file_size(path("plant.csv"))), kSizeLimit);
}

// GIVEN excite-plant --can logging to a 32 KiB tmpfs; WHEN the gateway streams a whole plan
// THEN the disk fills mid-run, the plant keeps serving to the end, and exits 3 naming ENOSPC.
TEST_F(CanDiskFull, ThePlantOnAFullDiskKeepsServingAndSaysWhy) {
  EXCITE_REQUIRE_SOCKETCAN(kBus);
  const fs::path small = path("small");
  fs::create_directories(small);
  ASSERT_EQ(::mount("excite-test", small.c_str(), "tmpfs", MS_NOSUID | MS_NODEV, "size=32k"), 0)
      << "mount tmpfs on " << small << ": " << std::strerror(errno) << " (root in the VM)";
  struct Unmount {
    fs::path dir;
    ~Unmount() { ::umount2(dir.c_str(), MNT_DETACH); }
  } unmount{small};
  loop_config(
      "woodberry2x2", 1502,
      "--transport can --interface " + std::string(kBus) + " --input-range 2 --period-s 0.005");
  plant_ = std::make_unique<PlantRunner>(
      std::vector<std::string>{"--config", path("plant.toml").string(), "--can", kBus, "--log",
                               (small / "plant.csv").string(), "--clock", "lockstep"},
      path("plant.stderr"));
  plant_->wait_listening();
  ASSERT_EQ(plant_->first_line(), "listening can " + std::string(kBus)) << plant_->stderr_text();
  stream_and_check(small / "plant.csv", "No space left on device (ENOSPC)");
}

}  // namespace
}  // namespace excite::test
