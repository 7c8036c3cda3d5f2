// SPDX-License-Identifier: MIT
// Issue 20: a bus flooded by a third node at a higher priority. vcan has no bit rate and no
// arbitration (a frame reaches the other sockets as soon as it is sent), so the test gives
// vcan1 both with queueing disciplines (toolchain/can-vm loads them; hal/can/README.md, "A bus
// flooded at a higher priority"):
//   tbf (token bucket) at 237 kbit/s on its 16-byte frames: 1852 frames/s, each the time of a
//       worst-case 8-byte frame (135 bits) on a 250 kbit/s bus;
//   prio inside it, bands by identifier (em_canid): 0x000..0x1FF first, then 0x200..0x2FF (the
//       gateway's setpoints and heartbeat), then the rest (the plant's answers): the order
//       arbitration gives them. The gateway's and plant's bands hold 10 frames (txqueuelen 10,
//       a CAN interface's default); a frame beyond is refused with ENOBUFS, as on a real
//       interface whose controller cannot win the bus.
// vcan is loaded with echo=1 (the VM's /init), so a frame reaches the other nodes when it
// leaves the queue, as a real controller's echo on transmit.
// A third node (cangen, can-utils) then sends 8-byte frames of identifier 0x0A0 back to back.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "can_loop_fixture.hpp"
#include "firmware/runlog/format.hpp"
#include "loop_facts.hpp"

namespace excite::test {
namespace {

constexpr const char* kShapedBus = "vcan1";
constexpr const char* kTc = "/usr/sbin/tc";
constexpr const char* kCangen = "/usr/bin/cangen";

// vcan1 shaped like a 250 kbit/s bus with arbitration by identifier band, for the test's life.
class ShapedBus {
 public:
  ShapedBus() {
    const std::string dev = std::string(" dev ") + kShapedBus + " ";
    const std::string tc = kTc;
    ok_ = shell(std::string("/sbin/ip link set ") + kShapedBus + " txqueuelen 10") &&
          shell(tc + " qdisc add" + dev + "root handle 1: tbf rate 237kbit burst 80 latency 1s") &&
          shell(tc + " qdisc add" + dev +
                "parent 1:1 handle 10: prio bands 3 priomap 2 2 2 2 2 2 2 2 2 2 2 2 2 2 2 2") &&
          shell(tc + " qdisc add" + dev + "parent 10:1 handle 11: pfifo limit 1000") &&
          shell(tc + " filter add" + dev +
                "parent 10: prio 1 basic match 'canid(sff 0x000:0x600)' flowid 10:1") &&
          shell(tc + " filter add" + dev +
                "parent 10: prio 2 basic match 'canid(sff 0x200:0x700)' flowid 10:2");
  }
  ~ShapedBus() { shell(std::string(kTc) + " qdisc del dev " + kShapedBus + " root 2>/dev/null"); }
  ShapedBus(const ShapedBus&) = delete;
  ShapedBus& operator=(const ShapedBus&) = delete;
  bool ok() const { return ok_; }

 private:
  bool ok_ = false;
};

// The heartbeat frames of a `candump -L` file: arrival times (s, the receiving socket's
// timestamps) and their uint16 values.
struct Heartbeats {
  std::vector<double> t;
  std::vector<unsigned> value;
};

Heartbeats heartbeats_in(const fs::path& dump) {
  Heartbeats h;
  std::ifstream in(dump);
  // "(1700000000.123456) vcan1 201#0100"
  for (std::string stamp, iface, frame; in >> stamp >> iface >> frame;) {
    h.t.push_back(std::stod(stamp.substr(1)));
    const std::string data = frame.substr(frame.find('#') + 1);
    h.value.push_back(static_cast<unsigned>(std::stoul(data.substr(0, 2), nullptr, 16) |
                                            std::stoul(data.substr(2, 2), nullptr, 16) << 8));
  }
  return h;
}

// The longest gap between consecutive arrivals in t[0, end): its length and the index of the
// arrival that ends it.
std::pair<double, std::size_t> longest_gap(const std::vector<double>& t, std::size_t end) {
  std::pair<double, std::size_t> worst{0.0, 0};
  for (std::size_t i = 1; i < std::min(end, t.size()); ++i) {
    if (t[i] - t[i - 1] > worst.first) worst = {t[i] - t[i - 1], i};
  }
  return worst;
}

class CanFlood : public CanLoop {};

// GIVEN woodberry2x2 streamed every 10 ms over vcan1 shaped like a 250 kbit/s bus (27 % load),
// the gateway's value frames stale after 100 ms, suspend_timeout_s = 1, the plant's watchdog
// 0.5 s;
// WHEN a third node floods the bus with identifier 0x0A0 (it wins arbitration over all of the
// loop's frames) for 2.5 s, then stops;
// THEN the gateway's frames are held off the bus for the flood (its heartbeat's longest gap on
// the wire ≥ 2 s); the gateway reports its value frames stale, flags the rows (comm-lost),
// suspends, aborts 1 s of the clock later (100 ticks: a CAN read does not block, so every tick
// runs and fails at once), and once the bus is free confirms the baseline (state safe, exit 6);
// the plant's watchdog tripped meanwhile and its own log ends at the baseline.
TEST_F(CanFlood, AHigherPriorityFloodHoldsTheLoopOffTheBusAndTheGatewayAbortsOnTheClock) {
  EXCITE_REQUIRE_SOCKETCAN(kShapedBus);
  ASSERT_EQ(access(kTc, X_OK), 0) << kTc << " not found (iproute2; the VM has it)";
  ASSERT_EQ(access(kCangen, X_OK), 0) << kCangen << " not found (can-utils)";
  ShapedBus shaped;
  ASSERT_TRUE(shaped.ok()) << "tc could not shape " << kShapedBus
                           << " (sch_tbf, sch_prio, cls_basic, em_canid loaded?)";
  const std::string plant = "woodberry2x2";
  const fs::path plan = design(plant, "prbsUnc");
  start_can_loop(plant, "--input-range 2 --period-s 0.01",
                 {"--clock", "lockstep", "--watchdog-s", "0.5"}, kShapedBus);
  real_time_gateway();
  {
    std::string t = slurp(path("gateway.toml"));
    t.replace(t.find("comm_fail_limit = 3"), 19, "comm_fail_limit = 3\nsuspend_timeout_s = 1");
    std::ofstream(path("gateway.toml")) << t;
  }
  PlantRunner heartbeats("/bin/sh",
                         {"-c", std::string("exec /usr/bin/candump -L ") + kShapedBus +
                                    ",201:7FF > " + path("heartbeats.log").string()},
                         path("candump.err"));
  std::this_thread::sleep_for(300ms);  // candump has bound its socket
  auto gw = start_gateway(plan, {"--start"});
  ASSERT_TRUE(wait_for_plant_samples("plant.csv", 200)) << gw->err();  // 2 s, past the ramp-in
  ASSERT_FALSE(gw->wait(0ms).has_value()) << gw->err();

  PlantRunner flood(kCangen, {kShapedBus, "-g", "0", "-I", "0A0", "-L", "8", "-D", "i"},
                    path("cangen.err"));
  const auto flood_start = Clock::now();
  std::this_thread::sleep_for(2500ms);
  EXPECT_FALSE(flood.wait_exit(0ms).has_value()) << "cangen ended: " << flood.stderr_text();
  flood.stop(SIGTERM);
  const double flood_s = std::chrono::duration<double>(Clock::now() - flood_start).count();

  const auto rc = gw->wait(120s);
  ASSERT_TRUE(rc.has_value()) << gw->err();
  const std::string err = gw->err();
  EXPECT_EQ(*rc, 6) << err;
  // The summary's CAN counts: the plant's frames held behind the flood (stale after 100 ms),
  // and the gateway's own refused by the full queue (ENOBUFS), as on a real interface.
  const std::string counts = "excite-gateway: can vcan1: ";
  const std::size_t at = err.find(counts);
  ASSERT_NE(at, std::string::npos) << err;
  const std::string line = err.substr(at, err.find('\n', at) - at);
  EXPECT_NE(line.find("(last: No buffer space available)"), std::string::npos) << line;
  const std::string stale = "reads with a value frame stale or missing ";
  ASSERT_NE(line.find(stale), std::string::npos) << line;
  const unsigned long stale_reads = std::stoul(line.substr(line.find(stale) + stale.size()));
  EXPECT_GE(stale_reads, 100U) << line;  // the whole suspension at least
  EXPECT_NE(err.find("aborted on suspension timeout"), std::string::npos) << err;
  EXPECT_NE(err.find("excite-gateway: safe after"), std::string::npos) << err;

  const runlog::RunLog log = read_log_or_fail(path("gw.csv"));
  ASSERT_GT(log.rows(), 0U);
  EXPECT_EQ(log.state.back(), runlog::RunState::safe);
  EXPECT_GT(rows_with(log, runlog::kCommLost), 0U) << "the late frames are not flagged";
  std::size_t suspended = log.rows();
  std::size_t aborted = log.rows();
  for (std::size_t r = 0; r < log.rows(); ++r) {
    if (suspended == log.rows() && log.state[r] == runlog::RunState::suspended) suspended = r;
    if (log.state[r] == runlog::RunState::aborted) {
      aborted = r;
      break;
    }
  }
  ASSERT_LT(suspended, aborted) << "no suspension before the abort";
  ASSERT_LT(aborted, log.rows()) << "no row in state aborted";
  const std::uint64_t clock_ticks = log.k[aborted] - log.k[suspended];
  EXPECT_GE(clock_ticks, 100U) << "aborted before suspend_timeout_s = 1 (100 ticks of 10 ms)";
  EXPECT_LT(clock_ticks, 100U + 50U) << "the abort came late";

  // On the wire: the gateway's heartbeat held off the bus for (nearly) the whole flood, and
  // regular before it (the shaping alone starves nothing).
  heartbeats.stop(SIGTERM);
  const Heartbeats hb = heartbeats_in(path("heartbeats.log"));
  ASSERT_GT(hb.t.size(), 200U);
  const auto [gap_s, after] = longest_gap(hb.t, hb.t.size());
  EXPECT_LT(longest_gap(hb.t, 150).first, 0.5) << "heartbeats held off before the flood";
  EXPECT_GE(gap_s, flood_s - 0.5) << "the gateway's frames were not held off the bus";
  EXPECT_LE(gap_s, flood_s + 1.0);
  // Late, not lost: the first heartbeat after the flood is the one after the last before it,
  // held in the queue; those queued (at most 10 frames: 5 ticks) follow back to back.
  ASSERT_GT(after, 0U);
  EXPECT_EQ(hb.value[after], (hb.value[after - 1] + 1) & 0xFFFF) << "the held frames were lost";
  std::size_t late = 1;
  while (after + late < hb.value.size() && hb.value[after + late] == hb.value[after] + late &&
         hb.t[after + late] - hb.t[after] < 0.02) {
    ++late;
  }
  EXPECT_LE(late, 5U) << "more held heartbeats than the queue's 10 frames";
  std::printf(
      "[ measured ] flood %.2f s: gateway heartbeat's longest gap on the bus %.3f s (ended "
      "%.3f s after the first), then %zu held heartbeats back to back; abort %llu ticks of the "
      "clock after the suspension, %zu rows executed between; rows comm-lost %zu; stale reads "
      "%lu\n",
      flood_s, gap_s, hb.t[after] - hb.t.front(), late,
      static_cast<unsigned long long>(clock_ticks), aborted - suspended,
      rows_with(log, runlog::kCommLost), stale_reads);

  const runlog::RunLog plant_log = stop_plant_and_read_its_log();
  const std::string plant_err = plant_->stderr_text();
  EXPECT_EQ(plant_err.find(" 0 watchdog trips"), std::string::npos)
      << "the plant's watchdog did not trip during the flood\n"
      << plant_err;
  ASSERT_GT(plant_log.rows(), 0U);
  for (std::size_t i = 0; i < plant_log.du.size(); ++i) {
    EXPECT_EQ(plant_log.du[i].back(), 0.0) << plant_log.input_names[i] << " not at the baseline";
  }
}

}  // namespace
}  // namespace excite::test
