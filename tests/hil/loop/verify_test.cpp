// SPDX-License-Identifier: MIT
// Verified writes with the real gateway and the real plant server (issue 10, items 1, 2, 4):
// a setpoint whose encoding disagrees with its readback is refused before anything is
// written, and a readback that does not follow the setpoints written stops the run, returns
// the plant to its baseline and says which channel, what was written and what came back.
// Each test asserts the exit code, the gateway's message and the plant's own run log.
#include <cmath>
#include <fstream>
#include <sstream>

#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

class Verify : public LoopTest {
 protected:
  // woodberry2x2, a real-time gateway ticking every 5 ms, a lock-step plant, no noise.
  void start() {
    start_loop(kPlant, "--input-range 2 --period-s 0.005 --noise-var 0", {"--clock", "lockstep"});
    plan_ = design(kPlant, "prbsUnc");
  }

  // Replaces the first occurrence of `from` at or after `after` in gateway.toml.
  void edit_gateway(const std::string& after, const std::string& from, const std::string& to) {
    const fs::path p = path("gateway.toml");
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const auto anchor = text.find(after);
    ASSERT_NE(anchor, std::string::npos) << after;
    const auto at = text.find(from, anchor);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    std::ofstream(p) << text;
  }

  // Every input the plant received stayed inside the limits.
  static void expect_plant_inside_limits(const runlog::RunLog& plant) {
    for (std::size_t i = 0; i < plant.du.size(); ++i) {
      EXPECT_LE(max_abs(plant.du[i]), kInputRange * (1 + 1e-6)) << plant.input_names[i];
    }
  }

  fs::path plan_;
};

// The case: u1 written as CDAB while its readback (the same holding register)
// decodes ABCD. Before: exit 0 while the plant received up to 6.7e33. Now: refused at
// configuration, nothing written.
TEST_F(Verify, WrongWordOrderOnOneSetpointIsRefusedBeforeAnythingIsWritten) {
  start();
  edit_gateway("name = \"u1\"", "word_order = \"ABCD\"", "word_order = \"CDAB\"");
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 2) << gw->err();
  EXPECT_NE(gw->err().find("(u1) register 100 = float32 CDAB"), std::string::npos) << gw->err();
  EXPECT_NE(gw->err().find("u1_sp reads the same register with (float32 ABCD)"), std::string::npos)
      << gw->err();
  EXPECT_FALSE(fs::exists(path("gw.csv")));
  // The plant logs one row per sample it took; nothing was written, so it took none (its
  // log holds the header only) or, if it did, every input is still at its baseline.
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0) << plant_->stderr_text();
  const runlog::ReadResult r = runlog::read_run_log(path("plant.csv").string());
  if (r.ok()) {
    for (std::size_t i = 0; i < r.log.du.size(); ++i) {
      EXPECT_EQ(max_abs(r.log.du[i]), 0.0) << r.log.input_names[i] << ": something was written";
    }
  } else {
    std::ifstream in(path("plant.csv"));
    std::size_t data = 0;
    for (std::string line; std::getline(in, line);) data += !line.empty() && line[0] != '#';
    EXPECT_LE(data, 1U) << "the plant log has rows but does not read back";
  }
}

// u1's readback mapped to y1's input register (a mis-mapped readback, as on a real PLC):
// it agrees at arm (both 0), then does not follow the setpoints written. The 4th mismatch
// in a row (readback_mismatch_limit 3) is a fault: excitation stops, the plant is returned
// to its baseline, and since the readback never confirms it, the state is "safe,
// unconfirmed" (exit 10).
TEST_F(Verify, AReadbackThatDoesNotFollowTheWritesStopsTheRunAndSaysWhatCameBack) {
  start();
  // y1 is no longer read as an output (values may not overlap); u1_sp reads its register.
  edit_gateway("[[values]]\nname = \"y1\"",
               "[[values]]\nname = \"y1\"\nunit = \"-\"\naddress = 200\nfunction_code = 4\ntype = "
               "\"float32\"\nword_order = \"ABCD\"\n\n",
               "");
  edit_gateway("name = \"u1_sp\"", "address = 100", "address = 200");
  edit_gateway("name = \"u1_sp\"", "function_code = 3", "function_code = 4");
  // A readback that never follows never confirms the baseline: give up as soon as allowed
  // (the two readbacks' hold, 2 × the 1 s response timeout) instead of after the default 60 s.
  edit_gateway("[gateway]", "comm_fail_limit = 3", "comm_fail_limit = 3\nconfirm_timeout_s = 0.1");
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 10) << gw->err();
  const std::string err = gw->err();
  EXPECT_NE(err.find("fault: verified write failed: setpoint u1 (register 100 float32 ABCD): "
                     "wrote "),
            std::string::npos)
      << err;
  EXPECT_NE(err.find(", read back "), std::string::npos) << err;
  EXPECT_NE(err.find(" from u1_sp at tick "), std::string::npos) << err;
  EXPECT_NE(err.find("safe, unconfirmed after"), std::string::npos) << err;
  EXPECT_NE(err.find("(fault: readback mismatch)"), std::string::npos) << err;

  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  // The excitation stopped: the row that says `aborted` comes early (the confirmation that
  // follows takes two readbacks a hold interval apart: 2 × the response timeout).
  std::size_t aborted_row = log.rows();
  for (std::size_t r = 0; r < log.rows() && aborted_row == log.rows(); ++r) {
    if (log.state[r] == runlog::RunState::aborted) aborted_row = r;
  }
  EXPECT_LT(aborted_row, 40U) << "the run was not stopped";
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  expect_plant_inside_limits(plant);
  ASSERT_GT(plant.rows(), 0U);
  for (std::size_t i = 0; i < plant.du.size(); ++i) {
    EXPECT_EQ(plant.du[i].back(), 0.0) << plant.input_names[i] << " is not back at baseline";
  }
}

// The same run with readback verification satisfied (the map as loop-config wrote it)
// completes and exits 0: the check does not cry wolf on float32 registers.
TEST_F(Verify, ACorrectMapCompletesWithoutMismatches) {
  start();
  auto gw = start_gateway(plan_, {"--start"});
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value());
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("readback mismatches 0"), std::string::npos) << gw->err();
  expect_plant_inside_limits(stop_plant_and_read_its_log());
}

}  // namespace
}  // namespace excite::test
