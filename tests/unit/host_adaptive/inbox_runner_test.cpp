// SPDX-License-Identifier: MIT
// Reading a run log the gateway is still writing, and the InboxRunner's hand-over, on real
// files without a gateway: a partial last line is not parsed; a segment's rows are its table
// rows (running, not flagged suspended) and the rows before them since the last call (the
// baseline held in real time); a run that ended, a refused segment, a stopped gateway and a
// timeout are named.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "firmware/runlog/format.hpp"
#include "host/adaptive/growing_log.hpp"
#include "host/adaptive/inbox_runner.hpp"
#include "host/adaptive/segments.hpp"
#include "host/design/case_studies.hpp"
#include "host/design/plan_file.hpp"
#include "host/design/presets.hpp"

namespace excite::host {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

const char* const kHeader =
    "# excite run log v3\n# producer: test (run 0123456789abcdef)\n# plant: p\n# plan: x\n# sample_time_min: 1\n"
    "# inputs: u1 u2\n# outputs: y1 y2\n# units: u1=- u2=- y1=- y2=-\n"
    "t_min,k,du_u1,du_u2,u_u1,u_u2,dy_y1,dy_y2,flags,state,segment\n";

// Row k: du = (k, -k), dy = (10k, -10k).
std::string row(int k, int flags, const char* state, int segment) {
  return std::to_string(k) + "," + std::to_string(k) + "," + std::to_string(k) + "," +
         std::to_string(-k) + ",0,0," + std::to_string(10 * k) + "," + std::to_string(-10 * k) +
         "," + std::to_string(flags) + "," + state + "," + std::to_string(segment) + "\n";
}

class GrowingLog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("excite_inbox_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_ / "inbox");
    // The gateway run the runner talks to (issue 39 §3): this process stands in for it.
    std::ofstream(dir_ / "inbox" / "gateway.run")
        << "run 0123456789abcdef\npid " << ::getpid() << "\nlog " << (dir_ / "gw.csv").string()
        << "\n";
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& text) { std::ofstream(dir_ / "gw.csv", std::ios::binary) << text; }
  fs::path dir_;
};

TEST_F(GrowingLog, APartialLastLineIsNotReadAndAnIncompleteHeaderIsNotYetALog) {
  EXPECT_FALSE(read_growing_log(dir_ / "gw.csv"));  // no file yet
  write(std::string(kHeader).substr(0, 60));
  EXPECT_FALSE(read_growing_log(dir_ / "gw.csv"));
  write(std::string(kHeader) + row(0, 0, "running", 0) + "1,1,0.5");
  const auto log = read_growing_log(dir_ / "gw.csv");
  ASSERT_TRUE(log);
  EXPECT_EQ(log->rows(), 1U);
  write(std::string(kHeader) + "1,1,abc,0,0,0,0,0,0,running,0\n");
  try {
    (void)read_growing_log(dir_ / "gw.csv");
    ADD_FAILURE() << "a bad row was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("du_u1 = 'abc', expected a number"), std::string::npos)
        << e.what();
  }
}

TEST_F(GrowingLog, ASegmentsRowsIncludeTheBaselineHeldBeforeThem) {
  // Segment 0: rows 0–2; the baseline held twice (real time); segment 1: rows 5–7.
  write(std::string(kHeader) + row(0, 0, "running", 0) + row(1, 0, "running", 0) +
        row(2, 0, "running", 0) + row(3, runlog::kSuspended, "running", 0) +
        row(4, runlog::kSuspended, "running", 0) + row(5, 0, "running", 1) +
        row(6, runlog::kRateLimited, "running", 1) + row(7, 0, "running", 1) +
        row(8, 0, "completed", 1));
  const auto log = read_growing_log(dir_ / "gw.csv");
  ASSERT_TRUE(log);
  const SegmentSpan s0 = find_segment(*log, 0, 0, 3);
  EXPECT_TRUE(s0.complete);
  EXPECT_EQ(s0.end, 3U);
  const SegmentSpan s1 = find_segment(*log, 1, s0.end, 3);
  EXPECT_TRUE(s1.complete);
  EXPECT_EQ(s1.end, 8U);  // rows 3–7: the two held rows first
  const SegmentSpan s2 = find_segment(*log, 2, s1.end, 3);
  EXPECT_FALSE(s2.complete);
  EXPECT_NE(s2.ended.find("row 8 (k = 8) is in state completed of segment 1 after 0 of 3 rows "
                          "of segment 2"),
            std::string::npos)
      << s2.ended;
}

TEST_F(GrowingLog, TheInboxRunnerHandsOverAndReturnsTheRowsAsLogged) {
  const PriorKnowledge prior = case_study("woodberry2x2");
  const plan::Plan first = cut_segment(*segment_sources(prior).plain.plan, 0, 3);
  InboxRunnerOptions o;
  o.inbox = dir_ / "inbox";
  o.run_log = dir_ / "gw.csv";
  o.segment_timeout = 300ms;
  int started = 0;
  int approved = 0;
  InboxHooks hooks;
  hooks.start = [&](const plan::Plan& p) {
    ++started;
    EXPECT_EQ(p.recipe.samples, 3U);
    write(std::string(kHeader) + row(0, 0, "running", 0) + row(1, 0, "running", 0) +
          row(2, 0, "running", 0) + row(3, runlog::kSuspended, "running", 0));
  };
  hooks.approve = [&](int k) {
    EXPECT_TRUE(fs::exists(dir_ / "inbox" / "next.plan"));  // in place, whole
    EXPECT_EQ(k, 1);  // a failed call does not move on to the next segment
    ++approved;
  };
  InboxRunner runner(o, hooks);
  const MeasuredSegment m0 = runner.run(first);
  EXPECT_EQ(started, 1);
  ASSERT_EQ(m0.du.rows(), 3);
  EXPECT_EQ(m0.du(2, 1), -2.0);
  EXPECT_EQ(m0.dy(2, 0), 20.0);
  // Segment 1 is never logged: the runner names the timeout and what it saw.
  try {
    (void)runner.run(first);
    ADD_FAILURE() << "no rows, yet returned";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("segment 1 (3 rows)"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0 rows logged after 300 ms"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(approved, 1);
  // Stopped on that error, the runner took its segment back (issue 39 §3: nothing a later
  // gateway would take is left behind).
  EXPECT_FALSE(fs::exists(dir_ / "inbox" / "next.plan"));
  // A next.plan the gateway has not taken: a hand-over is refused, naming the file, and
  // that file (not the runner's) is left alone.
  std::ofstream(dir_ / "inbox" / "next.plan") << "not taken";
  try {
    (void)runner.run(first);
    ADD_FAILURE() << "handed over twice";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("next.plan = present, expected absent"), std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(fs::exists(dir_ / "inbox" / "next.plan"));
  // Refused by the gateway, and a gateway that stopped: named.
  fs::rename(dir_ / "inbox" / "next.plan", dir_ / "inbox" / "next.plan.refused");
  try {
    (void)runner.run(first);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the gateway refused it"), std::string::npos) << e.what();
  }
  fs::remove(dir_ / "inbox" / "next.plan.refused");
  fs::remove(dir_ / "inbox" / "next.plan");
  InboxHooks gone = hooks;
  gone.gone = [] { return std::string("exit 6"); };
  InboxRunner stopped(o, gone);
  (void)stopped.run(first);
  try {
    (void)stopped.run(first);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("the gateway has stopped after 0 of its rows: exit 6"),
              std::string::npos)
        << e.what();
  }
}

TEST_F(GrowingLog, BadRunnerOptionsAreRefusedByName) {
  InboxRunnerOptions o;
  o.inbox = dir_ / "missing";
  InboxHooks hooks;
  hooks.start = [](const plan::Plan&) {};
  EXPECT_THROW(InboxRunner(o, hooks), std::invalid_argument);
  o.inbox = dir_ / "inbox";
  EXPECT_THROW(InboxRunner(o, InboxHooks{}), std::invalid_argument);
  o.poll = 0ms;
  EXPECT_THROW(InboxRunner(o, hooks), std::invalid_argument);
}

}  // namespace
}  // namespace excite::host
