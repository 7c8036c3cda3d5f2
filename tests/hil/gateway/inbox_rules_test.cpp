// SPDX-License-Identifier: MIT
// Issue 39 §3, with the real gateway and the real plant server over a real socket (lock-step):
// the inbox takes only what this run decided, and only a regular file of the gateway's user.
//  - a next.plan left in the inbox before the gateway starts is refused at start (named,
//    moved aside), even approved (before: staged, and taken with the first approval);
//  - a kept segment of an earlier run (segment-1.plan) is never overwritten: the new one is
//    kept as segment-1-2.plan (before: overwritten without a word);
//  - a symbolic link, a FIFO or a folder named next.plan is refused by name and moved aside
//    (before: the link was followed and taken, the FIFO and the folder ignored in silence);
//  - a file of another user is refused (root only: the test chowns it to nobody);
//  - a file written in place (no temporary name) and caught half-written is refused with a
//    message that says how to drop a segment atomically;
//  - an inbox folder others can write → exit 1 naming it, nothing written to the plant.
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <thread>

#include "../loop/loop_facts.hpp"
#include "../loop/loop_fixture.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

void write_bytes(const fs::path& p, const std::vector<std::uint8_t>& bytes) {
  std::ofstream(p, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
}

class InboxRules : public LoopTest {
 protected:
  void SetUp() override {
    plan_path_ = design(kPlant, "prbsUnc");
    plan::Plan running;
    ASSERT_TRUE(engine::load_plan(bytes_of(plan_path_), 2, signal::kTableCapacity, running));
    // A valid segment: the running plan itself, with the provenance of a segment.
    plan::set_text(running.meta.provenance, "excite test (hil inbox)");
    segment_.resize(plan::max_encoded_size());
    const plan::EncodeResult r = plan::encode(running, segment_);
    ASSERT_TRUE(r.status) << r.status.message();
    segment_.resize(r.size);
    fs::create_directories(inbox());
    fs::permissions(inbox(), fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                 fs::perms::others_read | fs::perms::others_exec);
  }

  fs::path inbox() const { return path("inbox"); }

  /// The atomic drop: a temporary name, then rename.
  void drop() {
    write_bytes(inbox() / ".next.plan.tmp", segment_);
    fs::rename(inbox() / ".next.plan.tmp", inbox() / "next.plan");
  }

  std::unique_ptr<GatewayProcess> start_armed(std::vector<std::string> extra = {}) {
    extra.insert(extra.end(), {"--clock", "lockstep", "--segment-inbox", inbox().string()});
    return start_gateway(plan_path_, extra);
  }

  static bool wait_for(GatewayProcess& gw, const std::string& what, std::size_t times = 1) {
    for (int i = 0; i < 2000; ++i) {
      if (count_of(gw.err(), what) >= times) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  /// Approves whatever is staged, starts, and expects the run to complete on `taken` segments.
  static void approve_start_and_complete(GatewayProcess& gw, const std::string& segments_line) {
    gw.send_line("approve");
    std::this_thread::sleep_for(300ms);
    gw.send_line("start");
    const auto rc = gw.wait(60s);
    ASSERT_TRUE(rc.has_value()) << gw.err();
    EXPECT_EQ(*rc, 0) << gw.err();
    EXPECT_NE(gw.err().find(segments_line), std::string::npos) << gw.err();
  }

  fs::path plan_path_;
  std::vector<std::uint8_t> segment_;
};

TEST_F(InboxRules, ASegmentLeftBeforeTheStartIsRefusedEvenApproved) {
  start_loop(kPlant, "--input-range 2");
  drop();  // an earlier run's decision
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  const std::string err = gw->err();
  EXPECT_NE(err.find("segment refused: " + (inbox() / "next.plan").string() +
                     ": present when the gateway started, expected a segment written during "
                     "this run"),
            std::string::npos)
      << err;
  EXPECT_NE(err.find("the file is now next.plan.refused"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(inbox() / "next.plan.refused"));
  approve_start_and_complete(*gw, "segments: 0 staged, 0 refused, 0 taken");
  EXPECT_FALSE(fs::exists(inbox() / "segment-1.plan"));
}

TEST_F(InboxRules, TakeWaitingSegmentTakesIt) {
  start_loop(kPlant, "--input-range 2");
  drop();
  auto gw = start_armed({"--take-waiting-segment"});
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  approve_start_and_complete(*gw, "segments: 1 staged, 0 refused, 1 taken");
}

TEST_F(InboxRules, AKeptSegmentOfAnEarlierRunIsNeverOverwritten) {
  start_loop(kPlant, "--input-range 2");
  const std::vector<std::uint8_t> earlier = {'e', 'a', 'r', 'l', 'i', 'e', 'r'};
  write_bytes(inbox() / "segment-1.plan", earlier);
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  drop();
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged: " + (inbox() / "segment-1-2.plan").string()))
      << gw->err();
  EXPECT_EQ(bytes_of(inbox() / "segment-1.plan"), earlier);
  EXPECT_EQ(bytes_of(inbox() / "segment-1-2.plan"), segment_);
  approve_start_and_complete(*gw, "segments: 1 staged, 0 refused, 1 taken");
}

TEST_F(InboxRules, ALinkAFifoAndAFolderAreRefusedByName) {
  start_loop(kPlant, "--input-range 2");
  write_bytes(path("elsewhere.plan"), segment_);
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  const fs::path next = inbox() / "next.plan";

  fs::create_symlink(path("elsewhere.plan"), next);
  ASSERT_TRUE(wait_for(*gw, "segment refused: ")) << gw->err();
  EXPECT_NE(gw->err().find("file = a symbolic link, expected a regular file"), std::string::npos)
      << gw->err();

  ASSERT_EQ(mkfifo(next.c_str(), 0600), 0);
  ASSERT_TRUE(wait_for(*gw, "segment refused: ", 2)) << gw->err();
  EXPECT_NE(gw->err().find("file = a FIFO, expected a regular file"), std::string::npos)
      << gw->err();

  fs::create_directory(next);
  ASSERT_TRUE(wait_for(*gw, "segment refused: ", 3)) << gw->err();
  EXPECT_NE(gw->err().find("file = a folder, expected a regular file"), std::string::npos)
      << gw->err();
  // Moved aside, each under a name of its own; the link itself kept as a link.
  EXPECT_TRUE(fs::is_symlink(inbox() / "next.plan.refused"));
  EXPECT_TRUE(fs::is_fifo(inbox() / "next.plan.refused-2"));
  EXPECT_TRUE(fs::is_directory(inbox() / "next.plan.refused-3"));
  EXPECT_FALSE(fs::exists(next));
  approve_start_and_complete(*gw, "segments: 0 staged, 3 refused, 0 taken");
}

TEST_F(InboxRules, AFileOfAnotherUserIsRefused) {
  if (geteuid() != 0) GTEST_SKIP() << "chown to nobody needs root (uid " << geteuid() << ")";
  start_loop(kPlant, "--input-range 2");
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  const fs::path tmp = inbox() / ".next.plan.tmp";
  write_bytes(tmp, segment_);
  ASSERT_EQ(chown(tmp.c_str(), 65534, 65534), 0);  // nobody
  fs::rename(tmp, inbox() / "next.plan");
  ASSERT_TRUE(wait_for(*gw, "segment refused: ")) << gw->err();
  EXPECT_NE(gw->err().find("file owner = uid 65534, expected this gateway's user (uid 0)"),
            std::string::npos)
      << gw->err();
  approve_start_and_complete(*gw, "segments: 0 staged, 1 refused, 0 taken");
}

TEST_F(InboxRules, AHalfWrittenFileIsRefusedSayingHowToDropASegment) {
  start_loop(kPlant, "--input-range 2");
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  {
    std::ofstream half(inbox() / "next.plan", std::ios::binary);  // in place: no temporary name
    half.write(reinterpret_cast<const char*>(segment_.data()), 17);
    half.flush();
    ASSERT_TRUE(wait_for(*gw, "segment refused: ")) << gw->err();
  }
  const std::string err = gw->err();
  EXPECT_NE(err.find("(17 bytes read: a file still being written?)"), std::string::npos) << err;
  EXPECT_NE(err.find("drop a segment atomically: write it to a temporary name in " +
                     inbox().string() + " and rename it to next.plan"),
            std::string::npos)
      << err;
  approve_start_and_complete(*gw, "segments: 0 staged, 1 refused, 0 taken");
}

TEST_F(InboxRules, AnInboxOthersCanWriteIsRefusedAtStart) {
  start_loop(kPlant, "--input-range 2");
  fs::permissions(inbox(), fs::perms::all);  // 0777
  auto gw = start_armed({"--start"});
  const auto rc = gw->wait(30s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 1) << gw->err();
  EXPECT_NE(gw->err().find("--segment-inbox = " + inbox().string() +
                           " (mode 0777: writable by others), expected a folder owned by this "
                           "user"),
            std::string::npos)
      << gw->err();
  EXPECT_FALSE(fs::exists(path("gw.csv")));
  // The plant took no sample: its log has a header and no row (lock-step: one per write).
  EXPECT_EQ(plant_->stop(SIGTERM).value_or(-1), 0);
  std::ifstream plant_log(path("plant.csv"));
  std::size_t rows = 0;
  bool past_header = false;
  for (std::string line; std::getline(plant_log, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (past_header) ++rows;
    past_header = true;  // the column line
  }
  EXPECT_EQ(rows, 0U) << "the plant received a write";
}

TEST_F(InboxRules, AnotherRunsSegmentIsRefusedAndOnlyThisRunsIsPreApproved) {
  start_loop(kPlant, "--input-range 2");
  std::ofstream(path("gateway.toml"), std::ios::app)
      << "\n[segments]\npreapproved_from = \"excite test\"\n";
  auto gw = start_armed();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  const std::string err0 = gw->err();
  const std::size_t at = err0.find("excite-gateway: run ");
  ASSERT_NE(at, std::string::npos) << err0;
  const std::string ours = err0.substr(at + 20, 16);
  const std::string other = ours == "0123456789abcdef" ? "fedcba9876543210" : "0123456789abcdef";
  EXPECT_TRUE(fs::exists(inbox() / "gateway.run"));
  EXPECT_NE(std::ifstream(inbox() / "gateway.run").peek(), EOF);

  plan::Plan p;
  ASSERT_TRUE(engine::load_plan(segment_, 2, signal::kTableCapacity, p));
  const auto drop_with = [&](const std::string& provenance) {
    plan::set_text(p.meta.provenance, provenance);
    std::vector<std::uint8_t> bytes(plan::max_encoded_size());
    const plan::EncodeResult r = plan::encode(p, bytes);
    ASSERT_TRUE(r.status);
    bytes.resize(r.size);
    write_bytes(inbox() / ".next.plan.tmp", bytes);
    fs::rename(inbox() / ".next.plan.tmp", inbox() / "next.plan");
  };
  drop_with("run " + other + ": excite test segment 1");  // an earlier run's decision
  ASSERT_TRUE(wait_for(*gw, "segment refused: ")) << gw->err();
  EXPECT_NE(gw->err().find("segment run = " + other + ", expected this run's " + ours),
            std::string::npos)
      << gw->err();
  drop_with("excite test segment 1");  // names no run: not pre-approved
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  EXPECT_NE(gw->err().find("not pre-approved: its provenance names no run, expected \"run " + ours +
                           "\""),
            std::string::npos)
      << gw->err();
  gw->send_line("start");  // no approve: nothing is taken
  const auto rc = gw->wait(60s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("segments: 1 staged, 1 refused, 0 taken"), std::string::npos)
      << gw->err();
  EXPECT_FALSE(fs::exists(inbox() / "gateway.run")) << "removed at exit";
}

}  // namespace
}  // namespace excite::test
