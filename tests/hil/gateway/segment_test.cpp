// SPDX-License-Identifier: MIT
// Issue 26 §1, with the real gateway and the real plant server over a real socket (lock-step):
// the gateway takes the next plan segment without a bump. The segment is dropped into the
// gateway's --segment-inbox as next.plan (a temporary file renamed) before the run starts,
// so the inbox thread has staged it while the gateway waits, armed, for its start command.
//  (a) approved over stdin: switched to after the last row of the running plan; the gateway
//      log's segment column goes 0 → 1 there, and the plant's own log follows the new table
//      from that row on; a segment whose provenance names the configuration's
//      [segments] preapproved_from is taken without `approve`;
//  (b) never approved: never taken; the run completes on the original plan, segment 0;
//  (c) bad segments (CRC, undecodable, channels, sample time, limits, values beyond the plan's
//      limits, distortion above gateway.max_distortion) are refused by name, renamed
//      next.plan.refused, and the run completes on the original plan with exit 0;
//  (d) a switch whose jump exceeds max_move: no move the plant receives exceeds max_move, and
//      the gateway flags the switch row rate_limited.
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include <modbus.h>

#include "../loop/loop_facts.hpp"
#include "../loop/loop_fixture.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/runlog/format.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

constexpr std::uint32_t kSegmentRows = 200;

std::vector<std::uint8_t> encoded(const plan::Plan& p) {
  std::vector<std::uint8_t> bytes(plan::max_encoded_size());
  const plan::EncodeResult r = plan::encode(p, bytes);
  EXPECT_TRUE(r.status) << r.status.message();
  bytes.resize(r.size);
  return bytes;
}

// A plan's table as the gateway generates it (the same signal core).
struct Table {
  std::vector<double> values;
  std::uint32_t channels = 0;
  std::uint32_t rows = 0;
  double at(std::uint32_t k, std::uint32_t c) const { return values[k * channels + c]; }
};

Table table_of(const plan::Plan& p) {
  Table t;
  std::vector<double> storage(signal::kTableCapacity);
  std::vector<double> scratch(signal::scratch_size(p.recipe));
  signal::TableView view;
  const auto s = engine::make_table(p, storage, scratch, view);
  EXPECT_TRUE(s) << s.message();
  t.channels = view.channels;
  t.rows = view.samples;
  t.values.assign(storage.begin(), storage.begin() + std::ptrdiff_t{view.channels} * view.samples);
  return t;
}

class Segments : public LoopTest {
 protected:
  void SetUp() override {
    plan_path_ = design(kPlant, "prbsUnc");
    ASSERT_TRUE(engine::load_plan(bytes_of(plan_path_), 2, signal::kTableCapacity, running_));
    fs::create_directories(inbox());
  }

  fs::path inbox() const { return path("inbox"); }

  // The next segment: the running plan's channels, limits and sample time, a step table of
  // kSegmentRows rows: +level / −level on the two channels for half of it, then reversed.
  plan::Plan step_segment(double level) const {
    plan::Plan p = running_;
    signal::Recipe& r = p.recipe;
    r = signal::Recipe{};
    r.channels = running_.recipe.channels;
    r.samples = kSegmentRows;
    r.source_count = 1;
    signal::Source& s = r.sources[0];
    s.kind = signal::SourceKind::steps;
    s.start = 0;
    s.length = kSegmentRows;
    s.steps.segment_count = 2;
    s.steps.segments[0] = {level, kSegmentRows / 2};
    s.steps.segments[1] = {-level, kSegmentRows / 2};
    for (std::uint32_t c = 0; c < r.channels; ++c) r.mix[c][0] = c % 2 == 0 ? 1.0 : -1.0;
    plan::set_text(p.meta.design_name, "steps");
    plan::set_text(p.meta.provenance, "excite test (hil segment)");
    return p;
  }

  // The smallest deviation limit of the plan.
  double plan_limit() const {
    double m = 1e300;
    for (std::uint32_t c = 0; c < running_.recipe.channels; ++c) {
      m = std::min({m, running_.meta.channels[c].max, -running_.meta.channels[c].min});
    }
    return m;
  }

  // A step inside every limit: the plan's, and the gateway's setpoint limits (baseline ± 2,
  // loop-config --input-range 2).
  double level() const { return std::min(0.5 * plan_limit(), 1.0); }

  // What the host tool does: write a temporary file, then rename it to next.plan.
  void drop(const std::vector<std::uint8_t>& bytes) {
    const fs::path tmp = inbox() / ".next.plan.tmp";
    std::ofstream(tmp, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
    fs::rename(tmp, inbox() / "next.plan");
  }

  // Waits until the gateway's stderr says `what` `times` times; false after 20 s.
  static bool wait_for(GatewayProcess& gw, const std::string& what, std::size_t times = 1) {
    for (int i = 0; i < 2000; ++i) {
      if (count_of(gw.err(), what) >= times) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  // The segment was dropped before the gateway started: --take-waiting-segment takes it
  // (without, it is refused as an earlier run's decision: inbox_rules_test.cpp).
  std::unique_ptr<GatewayProcess> start_waiting(std::vector<std::string> extra = {}) {
    extra.insert(extra.end(), {"--clock", "lockstep", "--segment-inbox", inbox().string(),
                               "--take-waiting-segment"});
    return start_gateway(plan_path_, extra);
  }

  // Index of the first row of segment 1, checking the column goes 0 … 0 1 … 1.
  static std::size_t first_row_of_segment_1(const runlog::RunLog& log) {
    std::size_t r1 = log.rows();
    for (std::size_t r = 0; r < log.rows(); ++r) {
      if (log.segment[r] == 1 && r1 == log.rows()) r1 = r;
      EXPECT_EQ(log.segment[r], r < r1 ? 0U : 1U) << "row " << r;
    }
    return r1;
  }

  fs::path plan_path_;
  plan::Plan running_;
};

TEST_F(Segments, AnApprovedSegmentIsTakenAtTheEndAndThePlantFollowsTheNewTable) {
  start_loop(kPlant, "--input-range 2");
  const plan::Plan next = step_segment(level());
  const Table t2 = table_of(next);
  drop(encoded(next));
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  EXPECT_NE(gw->err().find("waiting for approval"), std::string::npos) << gw->err();
  gw->send_line("approve");
  std::this_thread::sleep_for(500ms);  // one command slot: the approval is taken first
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  const std::string err = gw->err();
  EXPECT_NE(err.find("segment 0 -> 1"), std::string::npos) << err;
  EXPECT_NE(err.find("segments: 1 staged, 0 refused, 1 taken"), std::string::npos) << err;
  EXPECT_TRUE(fs::exists(inbox() / "segment-1.plan"));

  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  ASSERT_EQ(gwl.format_version, 3);
  const std::size_t r1 = first_row_of_segment_1(gwl);
  ASSERT_LT(r1 + kSegmentRows, gwl.rows());
  ASSERT_EQ(plant.rows(), gwl.rows());
  // The row before the switch is the last row of the running plan; from the switch on, the
  // gateway writes the new table and the plant receives it (float32 registers).
  const Table t1 = table_of(running_);
  for (std::uint32_t c = 0; c < 2; ++c) {
    const double scale = std::abs(gwl.u[c][r1]) + 1.0;
    EXPECT_NEAR(gwl.du[c][r1 - 1], t1.at(t1.rows - 1, c), 1e-12 * scale);
    for (std::uint32_t i = 0; i < kSegmentRows; ++i) {
      EXPECT_NEAR(gwl.du[c][r1 + i], t2.at(i, c), 1e-12 * scale) << "gateway row " << r1 + i;
      EXPECT_NEAR(plant.du[c][r1 + i], t2.at(i, c), 2 * kFloat32Epsilon * scale)
          << "plant row " << r1 + i;
    }
    EXPECT_LE(std::abs(plant.du[c].back()), 2 * kFloat32Epsilon * scale) << "back at baseline";
  }
  std::printf("[ measured ] switch at gateway row %zu of %zu; plant rows %zu\n", r1, gwl.rows(),
              plant.rows());
}

// The operator's other way to approve: value 5 in the command register, written by a Modbus
// client of the plant (as an operator station would write it) while the gateway, armed,
// reads the register every tick.
TEST_F(Segments, ASegmentApprovedByTheCommandRegisterIsTaken) {
  const std::uint16_t port = start_loop(kPlant, "--input-range 2");
  drop(encoded(step_segment(level())));
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  modbus_t* operator_station = modbus_new_tcp("127.0.0.1", port);
  ASSERT_NE(operator_station, nullptr);
  ASSERT_EQ(modbus_connect(operator_station), 0) << modbus_strerror(errno);
  constexpr int kCommandRegister = 301;  // loop-config's command value (sim/server default map)
  constexpr std::uint16_t kApprove = 5;
  ASSERT_EQ(modbus_write_register(operator_station, kCommandRegister, kApprove), 1)
      << modbus_strerror(errno);
  modbus_close(operator_station);
  modbus_free(operator_station);
  std::this_thread::sleep_for(500ms);  // the armed gateway reads it on its next ticks
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("segments: 1 staged, 0 refused, 1 taken"), std::string::npos)
      << gw->err();
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  EXPECT_LT(first_row_of_segment_1(gwl), gwl.rows());
  (void)stop_plant_and_read_its_log();
}

// Issue 39 §3: an approval is an edge the gateway acknowledges. loop-config's command value
// has `acknowledge = "clear"`: after each code it reads, the gateway writes 0 back. The first
// 5 (nothing staged yet) is dropped; the second 5 — the same value the first one left before
// this fix — approves the segment staged meanwhile. The operator station sees each
// acknowledgement as the register back at 0.
TEST_F(Segments, EachFiveInTheCommandRegisterIsSeenBecauseTheGatewayClearsIt) {
  const std::uint16_t port = start_loop(kPlant, "--input-range 2");
  auto gw = start_gateway(plan_path_, {"--clock", "lockstep", "--segment-inbox", inbox().string()});
  ASSERT_TRUE(wait_for(*gw, "waiting for start")) << gw->err();
  modbus_t* operator_station = modbus_new_tcp("127.0.0.1", port);
  ASSERT_NE(operator_station, nullptr);
  ASSERT_EQ(modbus_connect(operator_station), 0) << modbus_strerror(errno);
  constexpr int kCommandRegister = 301;  // loop-config's command value (sim/server default map)
  constexpr std::uint16_t kApprove = 5;
  const auto acknowledged = [&] {  // the register back at 0 within 5 s
    for (int i = 0; i < 500; ++i) {
      std::uint16_t code = kApprove;
      if (modbus_read_registers(operator_station, kCommandRegister, 1, &code) == 1 && code == 0) {
        return true;
      }
      std::this_thread::sleep_for(10ms);
    }
    return false;
  };
  ASSERT_EQ(modbus_write_register(operator_station, kCommandRegister, kApprove), 1);
  EXPECT_TRUE(acknowledged()) << "the first 5 (nothing staged: dropped) was not cleared";
  drop(encoded(step_segment(level())));
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  ASSERT_EQ(modbus_write_register(operator_station, kCommandRegister, kApprove), 1);
  EXPECT_TRUE(acknowledged()) << "the second 5 was not cleared";
  modbus_close(operator_station);
  modbus_free(operator_station);
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("segments: 1 staged, 0 refused, 1 taken"), std::string::npos)
      << gw->err();
  EXPECT_NE(gw->err().find("command register: cleared after 2 readings"), std::string::npos)
      << gw->err();
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  EXPECT_LT(first_row_of_segment_1(gwl), gwl.rows());
  (void)stop_plant_and_read_its_log();
}

TEST_F(Segments, ASegmentFromThePreApprovedToolIsTakenWithoutApproval) {
  start_loop(kPlant, "--input-range 2");
  std::ofstream(path("gateway.toml"), std::ios::app)
      << "\n[segments]\npreapproved_from = \"excite test\"\n";
  // Only a segment of this gateway run is pre-approved (issue 39 §3): its provenance names
  // the run the gateway drew at start (stderr `excite-gateway: run ID`).
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "armed")) << gw->err();
  const std::string err0 = gw->err();
  const std::size_t at = err0.find("excite-gateway: run ");
  ASSERT_NE(at, std::string::npos) << err0;
  plan::Plan next = step_segment(level());
  plan::set_text(next.meta.provenance,
                 "run " + err0.substr(at + 20, 16) + ": excite test (hil segment)");
  drop(encoded(next));
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  gw->send_line("start");  // no approve
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("pre-approved (segments.preapproved_from = \"excite test\")"),
            std::string::npos)
      << gw->err();
  EXPECT_NE(gw->err().find("segments: 1 staged, 0 refused, 1 taken"), std::string::npos)
      << gw->err();
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  EXPECT_LT(first_row_of_segment_1(gwl), gwl.rows());
  (void)stop_plant_and_read_its_log();
}

TEST_F(Segments, AnUnapprovedSegmentIsNeverTaken) {
  start_loop(kPlant, "--input-range 2");
  drop(encoded(step_segment(level())));
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  EXPECT_NE(gw->err().find("segments: 1 staged, 0 refused, 0 taken"), std::string::npos)
      << gw->err();
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(gwl.rows(), running_.recipe.samples);
  for (std::size_t r = 0; r < gwl.rows(); ++r) ASSERT_EQ(gwl.segment[r], 0U) << "row " << r;
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  ASSERT_EQ(plant.rows(), gwl.rows());
}

TEST_F(Segments, BadSegmentsAreRefusedByNameAndTheRunCompletesOnTheOriginalPlan) {
  start_loop(kPlant, "--input-range 2");
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "watching")) << gw->err();
  std::vector<std::pair<std::vector<std::uint8_t>, std::string>> bad;
  {
    std::vector<std::uint8_t> crc = encoded(step_segment(level()));
    crc[crc.size() / 2] ^= 0x01U;
    bad.push_back({crc, "CRC"});
  }
  const std::string text = "not a plan at all, but long enough to be read";
  bad.push_back({{text.begin(), text.end()}, "of the plan magic"});
  bad.push_back({bytes_of(design("alatiqi4x4", "prbsUnc")), "plan channels = 4, expected 2"});
  {
    plan::Plan p = step_segment(level());
    p.meta.sample_time_min *= 2.0;
    bad.push_back({encoded(p), "segment.sample_time_min = "});
  }
  {
    plan::Plan p = step_segment(level());
    p.meta.channels[1].max *= 2.0;
    bad.push_back({encoded(p), "segment.channels[1].max = "});
  }
  {
    plan::Plan p = step_segment(level());
    p.recipe.sources[0].steps.segments[0].level = 2.0 * plan_limit();  // beyond the plan's
    bad.push_back({encoded(p), ") = " + std::to_string(static_cast<int>(2.0 * plan_limit()))});
  }
  {
    plan::Plan p = step_segment(3.0);  // inside the plan's limits, beyond the gateway's ±2
    bad.push_back({encoded(p), "baseline + segment table = [-3, 3], expected within"});
  }
  {
    // Larger than any plan: refused by its size, not read.
    std::vector<std::uint8_t> huge(plan::max_encoded_size() + 1, 0x55U);
    bad.push_back(
        {huge, "file size = " + std::to_string(huge.size()) + " bytes, expected at most"});
  }
  for (std::size_t i = 0; i < bad.size(); ++i) {
    drop(bad[i].first);
    ASSERT_TRUE(wait_for(*gw, "segment refused: ", i + 1)) << "bad segment " << i << gw->err();
    EXPECT_FALSE(fs::exists(inbox() / "next.plan"));
    EXPECT_TRUE(fs::exists(inbox() / "next.plan.refused"));
  }
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 0) << err;
  for (const auto& [bytes, message] : bad) {
    EXPECT_NE(err.find(message), std::string::npos) << "expected a refusal naming " << message;
  }
  EXPECT_EQ(count_of(err, "; the running segment 0 continues"), bad.size()) << err;
  EXPECT_NE(err.find("segments: 0 staged, 8 refused, 0 taken"), std::string::npos) << err;
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  for (std::size_t r = 0; r < gwl.rows(); ++r) ASSERT_EQ(gwl.segment[r], 0U) << "row " << r;
  (void)stop_plant_and_read_its_log();
}

TEST_F(Segments, ASegmentThatWouldDistortBeyondMaxDistortionIsRefused) {
  // max_move just above what the running plan asks for: the step segment's jumps exceed it.
  const Table t1 = table_of(running_);
  double largest = 0.0;
  for (std::uint32_t k = 0; k <= t1.rows; ++k) {
    for (std::uint32_t c = 0; c < 2; ++c) {
      const double a = k == 0 ? 0.0 : t1.at(k - 1, c);
      const double b = k == t1.rows ? 0.0 : t1.at(k, c);
      largest = std::max(largest, std::abs(b - a));
    }
  }
  ASSERT_GT(2.0 * level(), 1.01 * largest) << "the step segment must jump further";
  start_loop(kPlant, "--input-range 2 --max-move " + std::to_string(1.01 * largest));
  auto gw = start_waiting();
  ASSERT_TRUE(wait_for(*gw, "watching")) << gw->err();
  drop(encoded(step_segment(level())));
  ASSERT_TRUE(wait_for(*gw, "segment refused: ")) << gw->err();
  EXPECT_NE(gw->err().find("the plan would be distorted"), std::string::npos) << gw->err();
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  (void)stop_plant_and_read_its_log();
}

TEST_F(Segments, NoMoveThePlantReceivesAtTheSwitchExceedsMaxMove) {
  // GIVEN a segment whose first row lies further from the running plan's last row than
  // max_move (the jump at the switch), and the gateway allowed to rate-limit it
  const plan::Plan next = step_segment(level());
  const Table t1 = table_of(running_);
  const Table t2 = table_of(next);
  double jump = 0.0;
  for (std::uint32_t c = 0; c < 2; ++c) {
    jump = std::max(jump, std::abs(t2.at(0, c) - t1.at(t1.rows - 1, c)));
  }
  const double max_move = jump / 3.0;
  start_loop(kPlant, "--input-range 2 --max-move " + std::to_string(max_move));
  const double written_max_move = std::stod(std::to_string(max_move));
  drop(encoded(next));
  // WHEN it is approved and the run streams through the switch
  auto gw = start_waiting({"--allow-distortion"});
  ASSERT_TRUE(wait_for(*gw, "segment 1 staged")) << gw->err();
  gw->send_line("approve");
  std::this_thread::sleep_for(500ms);
  gw->send_line("start");
  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  EXPECT_EQ(*rc, 0) << gw->err();
  // THEN the switch row is rate-limited and no move the plant received exceeds max_move
  const runlog::RunLog gwl = read_log_or_fail(path("gw.csv"));
  const runlog::RunLog plant = stop_plant_and_read_its_log();
  const std::size_t r1 = first_row_of_segment_1(gwl);
  ASSERT_LT(r1, gwl.rows());
  EXPECT_NE(gwl.flags[r1] & runlog::kRateLimited, 0U);
  double largest = 0.0;
  double at_switch = 0.0;
  for (std::uint32_t c = 0; c < 2; ++c) {
    const double tolerance = 4 * kFloat32Epsilon * (std::abs(plant.u[c][0]) + 2.0);
    for (std::size_t k = 1; k < plant.rows(); ++k) {
      const double move = std::abs(plant.u[c][k] - plant.u[c][k - 1]);
      largest = std::max(largest, move);
      if (k + 3 >= r1 && k <= r1 + 3) at_switch = std::max(at_switch, move);
      EXPECT_LE(move, written_max_move + tolerance) << "plant row " << k << " input " << c;
    }
  }
  EXPECT_GT(at_switch, 0.99 * written_max_move);  // the switch did move at full speed
  std::printf(
      "[ measured ] jump at the switch %.4g, max_move %.4g; largest move at the plant %.4g, "
      "around the switch %.4g\n",
      jump, written_max_move, largest, at_switch);
}

}  // namespace
}  // namespace excite::test
