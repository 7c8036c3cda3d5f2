// SPDX-License-Identifier: MIT
// excite-plant against misbehaving clients, as a process over real loopback sockets: one
// client dripping a request, half-open and idle connections, a stalled reply, more
// observers than connection slots, unserved function codes (FC07, FC22, FC23) and a
// malformed frame — while a well-behaved client (bare libmodbus) keeps being answered.
// Also the command line without --config (default register map), bad numbers refused by
// name, and a value that does not fit its register counted and reported.
#include <arpa/inet.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <modbus.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <thread>
#include <vector>

#include "firmware/app/timing_range.hpp"
#include "hal/modbus/modbus_field_bus.hpp"
#include "plant_runner.hpp"
#include "sim/plants/plant.hpp"
#include "sim/server/default_map.hpp"

namespace excite::sim::server {
namespace {

using test::PlantRunner;
using test::TempDir;
using ::testing::HasSubstr;
using Clock = std::chrono::steady_clock;

// A raw TCP connection to the plant, for sending exactly the bytes a test wants.
class RawClient {
 public:
  explicit RawClient(std::uint16_t port) {
    fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = connect(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  }
  ~RawClient() {
    if (fd_ != -1) close(fd_);
  }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return connected_; }
  bool send_bytes(const std::vector<std::uint8_t>& bytes) {
    return send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(bytes.size());
  }
  // Bytes received within `timeout`; empty on timeout; `closed` set when the peer closed.
  std::vector<std::uint8_t> receive(std::chrono::milliseconds timeout, bool& closed) {
    closed = false;
    pollfd p{fd_, POLLIN, 0};
    if (poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return {};
    std::array<std::uint8_t, 300> buffer{};
    const ssize_t n = recv(fd_, buffer.data(), buffer.size(), 0);
    if (n <= 0) {
      closed = true;
      return {};
    }
    return {buffer.begin(), buffer.begin() + n};
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
};

// MBAP header + PDU for transaction `tid`, unit 1.
std::vector<std::uint8_t> frame(std::uint16_t tid, const std::vector<std::uint8_t>& pdu) {
  const auto length = static_cast<std::uint16_t>(pdu.size() + 1);
  std::vector<std::uint8_t> out{
      static_cast<std::uint8_t>(tid >> 8),    static_cast<std::uint8_t>(tid & 0xFF),    0, 0,
      static_cast<std::uint8_t>(length >> 8), static_cast<std::uint8_t>(length & 0xFF), 1};
  for (const std::uint8_t byte : pdu) out.push_back(byte);  // (insert: a GCC 12 false warning)
  return out;
}

const std::vector<std::uint8_t> kReadValues{0x04, 0x00, 200, 0x00, 0x08};  // FC04 200..207

class Robust : public ::testing::Test {
 protected:
  // excite-plant --plant alatiqi4x4 with the default register map, lock-step.
  void start(std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"--plant",     "alatiqi4x4", "--modbus-tcp",
                                  "127.0.0.1:0", "--clock",    "lockstep"};
    args.insert(args.end(), extra.begin(), extra.end());
    plant_.emplace(args, dir_.path() / "stderr.txt");
    const auto port = plant_->wait_listening();
    ASSERT_TRUE(port) << plant_->first_line() << plant_->stderr_text();
    port_ = *port;
  }

  modbus_t* client(int timeout_ms = 300) {
    modbus_t* ctx = modbus_new_tcp("127.0.0.1", port_);
    EXPECT_NE(ctx, nullptr);
    modbus_set_response_timeout(ctx, 0, static_cast<std::uint32_t>(timeout_ms) * 1000U);
    EXPECT_EQ(modbus_connect(ctx), 0) << modbus_strerror(errno);
    clients_.push_back(ctx);
    return ctx;
  }

  void TearDown() override {
    for (modbus_t* ctx : clients_) {
      modbus_close(ctx);
      modbus_free(ctx);
    }
  }

  // Polls the values `count` times; returns how many were answered, and the slowest.
  int poll_values(modbus_t* ctx, int count, std::chrono::milliseconds& slowest,
                  std::chrono::milliseconds gap = std::chrono::milliseconds(0)) {
    int answered = 0;
    slowest = std::chrono::milliseconds(0);
    for (int i = 0; i < count; ++i) {
      std::array<std::uint16_t, 8> regs{};
      const auto t0 = Clock::now();
      if (modbus_read_input_registers(ctx, 200, 8, regs.data()) == 8) ++answered;
      slowest = std::max(slowest,
                         std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0));
      std::this_thread::sleep_for(gap);
    }
    return answered;
  }

  TempDir dir_;
  std::optional<PlantRunner> plant_;
  std::uint16_t port_ = 0;
  std::vector<modbus_t*> clients_;
};

TEST_F(Robust, DrippingClientBlocksNobodyAndIsClosedAfterThePartialTimeout) {
  start();
  RawClient dripper(port_);
  ASSERT_TRUE(dripper.connected());
  // GIVEN a client sending a request one byte every 0.3 s (a 12-byte request takes 3.6 s)
  std::atomic<bool> done{false};
  std::atomic<int> sent{0};
  std::thread drip([&] {
    const auto request = frame(1, kReadValues);
    for (const std::uint8_t byte : request) {
      if (done || !dripper.send_bytes({byte})) break;
      ++sent;
      std::this_thread::sleep_for(std::chrono::milliseconds(300));
    }
  });
  // WHEN another client polls 12 times meanwhile
  std::chrono::milliseconds slowest{};
  const int answered = poll_values(client(), 12, slowest, std::chrono::milliseconds(100));
  // THEN every poll is answered promptly (before: 0 of 12 in 30 s)
  EXPECT_EQ(answered, 12);
  EXPECT_LT(slowest.count(), 150);
  // AND the dripping request is cut off once it has been partial for 2 s
  bool closed = false;
  const auto t0 = Clock::now();
  while (!closed && Clock::now() - t0 < std::chrono::seconds(5)) {
    dripper.receive(std::chrono::milliseconds(100), closed);
  }
  done = true;
  drip.join();
  EXPECT_TRUE(closed);
  EXPECT_LT(sent.load(), 12);  // closed before the request was complete
}

TEST_F(Robust, HalfOpenAndIdleConnectionsCostNothingAndAreClosedWhenIdle) {
  start({"--idle-timeout-s", "0.5"});
  // GIVEN five connections that never send a byte and three that sent half a header
  std::vector<std::unique_ptr<RawClient>> silent;
  for (int i = 0; i < 5; ++i) silent.push_back(std::make_unique<RawClient>(port_));
  for (int i = 0; i < 3; ++i) {
    silent.push_back(std::make_unique<RawClient>(port_));
    ASSERT_TRUE(silent.back()->send_bytes({0x00, 0x01, 0x00}));
  }
  // WHEN a well-behaved client polls
  std::chrono::milliseconds slowest{};
  EXPECT_EQ(poll_values(client(), 10, slowest), 10);
  // THEN none waits on them (before: 0.5 s per half-open connection)
  EXPECT_LT(slowest.count(), 150);
  // AND every silent connection is closed by the server within the idle/partial bounds
  for (auto& c : silent) {
    bool closed = false;
    const auto t0 = Clock::now();
    while (!closed && Clock::now() - t0 < std::chrono::seconds(4)) {
      c->receive(std::chrono::milliseconds(100), closed);
    }
    EXPECT_TRUE(closed);
  }
}

TEST_F(Robust, GatewayConnectionIsNeverEvictedForIdleObserversNorForIdleness) {
  start({"--idle-timeout-s", "0.3"});
  // GIVEN the gateway's connection, the one writing the heartbeat
  modbus_t* gateway = client();
  ASSERT_EQ(modbus_write_register(gateway, 108, 1), 1) << modbus_strerror(errno);
  // WHEN twelve observers connect (8 slots) and the gateway stays idle past the timeout
  std::vector<std::unique_ptr<RawClient>> observers;
  for (int i = 0; i < 12; ++i) {
    observers.push_back(std::make_unique<RawClient>(port_));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  // THEN its connection still serves (no reconnect: a closed socket would fail here)
  std::uint16_t echo = 0;
  EXPECT_EQ(modbus_read_input_registers(gateway, 300, 1, &echo), 1) << modbus_strerror(errno);
  EXPECT_EQ(echo, 1);
  ASSERT_EQ(modbus_write_register(gateway, 108, 2), 1) << modbus_strerror(errno);
  EXPECT_EQ(modbus_read_input_registers(gateway, 300, 1, &echo), 1);
  EXPECT_EQ(echo, 2);
}

TEST_F(Robust, StalledReplyOnOneConnectionDoesNotDelayAnother) {
  start();
  modbus_t* harness = client();
  ASSERT_EQ(modbus_write_register(harness, 400, 1500), 1);  // stall 1.5 s
  ASSERT_EQ(modbus_write_register(harness, 401, 1), 1);     // one request
  RawClient stalled(port_);
  ASSERT_TRUE(stalled.send_bytes(frame(7, kReadValues)));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::chrono::milliseconds slowest{};
  EXPECT_EQ(poll_values(client(), 5, slowest), 5);
  EXPECT_LT(slowest.count(), 150);
  bool closed = false;
  const auto reply = stalled.receive(std::chrono::milliseconds(3000), closed);
  ASSERT_EQ(reply.size(), 9U + 16U);  // answered after the stall, not lost
  EXPECT_EQ(reply[1], 7);
}

// Found by tests/fuzz/modbus_request_fuzz: libmodbus answers a register count outside the
// Modbus range only after sleeping its response timeout (0.5 s) and flushing the socket,
// which stalled the whole server. Now refused at once with exception 3 (illegal data value).
TEST_F(Robust, RegisterCountOutOfRangeIsRefusedAtOnceAndDelaysNobody) {
  start();
  RawClient raw(port_);
  ASSERT_TRUE(raw.connected());
  const std::vector<std::vector<std::uint8_t>> bad{
      {0x04, 0x00, 200, 0x00, 0x00},                    // FC04, 0 registers
      {0x03, 0x00, 100, 0x00, 126},                     // FC03, 126 registers
      {0x10, 0x00, 100, 0x00, 0x02, 0x02, 0x00, 0x01},  // FC16, 2 registers, 2 bytes
  };
  std::uint16_t tid = 20;
  for (const auto& pdu : bad) {
    const auto t0 = Clock::now();
    ASSERT_TRUE(raw.send_bytes(frame(tid, pdu)));
    bool closed = false;
    const auto reply = raw.receive(std::chrono::milliseconds(2000), closed);
    const auto took = std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - t0);
    ASSERT_EQ(reply.size(), 9U) << "function code " << int{pdu[0]};
    EXPECT_EQ(reply[1], tid);
    EXPECT_EQ(reply[7], pdu[0] | 0x80);
    EXPECT_EQ(reply[8], 3);  // illegal data value
    EXPECT_LT(took.count(), 200) << "function code " << int{pdu[0]};
    ++tid;
  }
  std::chrono::milliseconds slowest{};
  EXPECT_EQ(poll_values(client(), 3, slowest), 3);  // the server serves on
}

TEST_F(Robust, UnservedFunctionCodesAreIllegalFunctionAndTouchNothing) {
  start();
  modbus_t* ctx = client();
  ASSERT_EQ(modbus_write_register(ctx, 108, 5), 1);  // heartbeat 5: one sample, echo 5
  // FC22 (mask write) and FC23 (read/write) on the heartbeat: refused, no sample, no echo
  EXPECT_EQ(modbus_mask_write_register(ctx, 108, 0x0000, 0x0009), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  const std::uint16_t nine = 9;
  std::uint16_t read = 0;
  EXPECT_EQ(modbus_write_and_read_registers(ctx, 108, 1, &nine, 300, 1, &read), -1);
  EXPECT_EQ(errno, EMBXILFUN);
  std::uint16_t hb = 0;
  ASSERT_EQ(modbus_read_registers(ctx, 108, 1, &hb), 1);
  EXPECT_EQ(hb, 5);
  std::uint16_t echo = 0;
  ASSERT_EQ(modbus_read_input_registers(ctx, 300, 1, &echo), 1);
  EXPECT_EQ(echo, 5);
  // FC07 (read exception status) and FC01 (coils) on a raw socket: exception 1, link kept
  RawClient raw(port_);
  for (const std::uint8_t fc : {std::uint8_t{0x07}, std::uint8_t{0x01}}) {
    const std::vector<std::uint8_t> pdu =
        fc == 0x07 ? std::vector<std::uint8_t>{fc} : std::vector<std::uint8_t>{fc, 0, 0, 0, 1};
    ASSERT_TRUE(raw.send_bytes(frame(3, pdu)));
    bool closed = false;
    const auto reply = raw.receive(std::chrono::milliseconds(1000), closed);
    ASSERT_FALSE(closed) << "FC" << int(fc) << " reset the connection";
    ASSERT_EQ(reply.size(), 9U);
    EXPECT_EQ(reply[7], fc | 0x80);
    EXPECT_EQ(reply[8], 0x01);  // illegal function
  }
  ASSERT_TRUE(raw.send_bytes(frame(4, kReadValues)));
  bool closed = false;
  EXPECT_EQ(raw.receive(std::chrono::milliseconds(1000), closed).size(), 9U + 16U);
  ASSERT_EQ(plant_->stop(SIGTERM), 0);
  EXPECT_THAT(plant_->stderr_text(), HasSubstr("4 illegal functions"));
}

TEST_F(Robust, MalformedFrameClosesOnlyItsConnection) {
  start();
  modbus_t* ctx = client();
  RawClient raw(port_);
  ASSERT_TRUE(raw.send_bytes({0, 1, 0x12, 0x34, 0, 6, 1, 4, 0, 200, 0, 1}));  // protocol ≠ 0
  bool closed = false;
  raw.receive(std::chrono::milliseconds(1000), closed);
  EXPECT_TRUE(closed);
  std::chrono::milliseconds slowest{};
  EXPECT_EQ(poll_values(ctx, 3, slowest), 3);
}

TEST_F(Robust, DefaultRegisterMapServesTheGatewaysFieldBusInLockstep) {
  start();
  hal::modbus::ModbusConfig bus_config;
  bus_config.device.port = port_;
  bus_config.device.response_timeout_ms = 300;
  bus_config.map = default_registers(4, 4).map;
  hal::modbus::ModbusFieldBus bus;
  ASSERT_TRUE(bus.configure(bus_config).ok());
  std::array<double, 4> y{};
  const std::array<double, 4> step{1.0, 0.0, 0.0, 0.0};
  int moves = 0;
  std::array<double, 4> previous{};
  for (std::uint16_t k = 1; k <= 30; ++k) {
    ASSERT_EQ(bus.exchange(step, k, y), hal::StatusCode::ok) << bus.detail();
    moves += y != previous ? 1 : 0;
    previous = y;
  }
  // One sample per heartbeat: after the plant's dead time the response moves every tick.
  EXPECT_GE(moves, 20);
  modbus_t* ctx = client();
  std::uint16_t command = 1;
  ASSERT_EQ(modbus_read_registers(ctx, 301, 1, &command), 1);  // the command register
  EXPECT_EQ(command, 0);
  ASSERT_EQ(modbus_write_register(ctx, 301, 4), 1);  // an operator can write it
}

TEST_F(Robust, RealtimeSpeedupRunsThePlantFaster) {
  plant_.emplace(std::vector<std::string>{"--plant", "alatiqi4x4", "--modbus-tcp", "127.0.0.1:0",
                                          "--clock", "realtime", "--speedup", "60000"},
                 dir_.path() / "stderr.txt");
  ASSERT_TRUE(plant_->wait_listening());
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(plant_->stop(SIGTERM), 0);
  // 1 ms per 1-min sample: about 500 samples in 0.5 s; at least 100 on a loaded machine
  const std::string text = plant_->stderr_text();
  const auto at = text.find("stopped after ");
  ASSERT_NE(at, std::string::npos) << text;
  EXPECT_GT(std::stoul(text.substr(at + 14)), 100UL) << text;
}

TEST_F(Robust, ValueOutsideItsRegisterRangeIsCountedAndReported) {
  // GIVEN a uint16 output whose range [0, 2] its baseline 5 already leaves
  const auto config = dir_.write("plant.toml", R"(
[plant]
library = "woodberry2x2"
output_baseline = [1.0, 5.0]
[registers]
heartbeat_address = 104
heartbeat_echo_address = 300
heartbeat_echo_function_code = 4
control_address = 400
[[registers.setpoints]]
address = 100
[[registers.setpoints]]
address = 102
[[registers.values]]
address = 200
function_code = 4
[[registers.values]]
name = "xB"
address = 202
function_code = 4
type = "uint16"
eng_min = 0.0
eng_max = 2.0
)");
  plant_.emplace(std::vector<std::string>{"--config", config.string(), "--modbus-tcp",
                                          "127.0.0.1:0", "--clock", "lockstep"},
                 dir_.path() / "stderr.txt");
  const auto port = plant_->wait_listening();
  ASSERT_TRUE(port);
  port_ = *port;
  modbus_t* ctx = client();
  // WHEN seven samples are taken
  for (std::uint16_t k = 1; k <= 7; ++k) ASSERT_EQ(modbus_write_register(ctx, 104, k), 1);
  // THEN the control block counts seven misfits, the register holds the range's end
  std::uint16_t count = 0;
  ASSERT_EQ(modbus_read_registers(ctx, 405, 1, &count), 1);
  EXPECT_EQ(count, 7);
  std::uint16_t raw = 0;
  ASSERT_EQ(modbus_read_input_registers(ctx, 202, 1, &raw), 1);
  EXPECT_EQ(raw, 65535);
  // AND stderr says so at once and in the summary at stop
  ASSERT_EQ(plant_->stop(SIGTERM), 0);
  const std::string text = plant_->stderr_text();
  EXPECT_THAT(text, HasSubstr("sample 0: output y2 = 5 does not fit its register"));
  EXPECT_THAT(text, HasSubstr("output y2: 7 samples outside its register's range [0, 2] "
                              "(lowest 5, highest 5)"));
  EXPECT_THAT(text, HasSubstr("7 values did not fit their registers"));
}

// Interoperability with a client we did not write: mbpoll (Debian package) writes a float
// setpoint and the heartbeat, and reads the outputs, through the non-blocking framing.
TEST_F(Robust, MbpollWritesAndReadsTheServer) {
  constexpr const char* kMbpoll = "/usr/bin/mbpoll";
  if (!std::filesystem::exists(kMbpoll)) GTEST_SKIP() << "mbpoll is not installed (Debian: mbpoll)";
  plant_.emplace(std::vector<std::string>{"--plant", "woodberry2x2", "--modbus-tcp", "127.0.0.1:0",
                                          "--clock", "lockstep"},
                 dir_.path() / "stderr.txt");
  const auto port = plant_->wait_listening();
  ASSERT_TRUE(port);
  const auto out = dir_.path() / "mbpoll.txt";
  const auto mbpoll = [&](std::vector<std::string> args) {
    std::vector<std::string> all{"-m", "tcp", "-p", std::to_string(*port), "-a", "1",
                                 "-0", "-B",  "-1"};
    all.insert(all.end(), args.begin(), args.end());
    return test::run_to_completion(kMbpoll, all, out);
  };
  const auto text = [&] {
    std::ifstream in(out);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  // u1 = 1.5 (float32 ABCD at 100), then five heartbeats (holding 104): five samples
  ASSERT_EQ(mbpoll({"-r", "100", "-t", "4:float", "127.0.0.1", "1.5"}), 0) << text();
  for (int k = 1; k <= 5; ++k) {
    ASSERT_EQ(mbpoll({"-r", "104", "-t", "4", "127.0.0.1", std::to_string(k)}), 0) << text();
  }
  ASSERT_EQ(mbpoll({"-r", "200", "-t", "3:float", "-c", "2", "127.0.0.1"}), 0) << text();
  const std::string values = text();
  const auto reference = make_plant("woodberry2x2");
  reference->reset(1.0);
  std::array<double, 2> dy{};
  for (int k = 0; k < 5; ++k) reference->step(std::array<double, 2>{1.5, 0.0}, dy);
  const auto at = values.find("[200]:");
  ASSERT_NE(at, std::string::npos) << values;
  const double y1 = std::stod(values.substr(at + 6));
  EXPECT_GT(dy[0], 0.5);  // the plant responded
  EXPECT_NEAR(y1, dy[0], 1e-5 * std::abs(dy[0])) << values;
  ASSERT_EQ(plant_->stop(SIGTERM), 0);
  EXPECT_THAT(plant_->stderr_text(), HasSubstr("stopped after 5 samples"));
}

struct Refusal {
  int exit_code;
  std::string first_line;
  std::string stderr_text;
};

Refusal refused(const std::vector<std::string>& args) {
  TempDir dir;
  PlantRunner plant(args, dir.path() / "stderr.txt");
  EXPECT_FALSE(plant.wait_listening());
  const auto code = plant.wait_exit();
  return {code.value_or(-1), plant.first_line(), plant.stderr_text()};
}

TEST(RobustBadInput, NanAndNegativeNumbersAreRefusedByName) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--plant", "alatiqi4x4", "--noise-var", "nan"}, "--noise-var = nan, expected"},
      {{"--plant", "alatiqi4x4", "--noise-var", "-1"},
       "--noise-var = -1, expected a variance >= 0"},
      {{"--plant", "alatiqi4x4", "--clock", "realtime", "--speedup", "-2"},
       "--speedup = -2, expected a factor > 0"},
      {{"--plant", "alatiqi4x4", "--clock", "lockstep", "--speedup", "2"},
       "--speedup = 2, expected only with --clock realtime"},
      {{"--plant", "alatiqi4x4", "--sample-time-min", "0"}, "--sample-time-min = 0, expected"},
      {{"--plant", "alatiqi4x4", "--modbus-tcp", "127.0.0.1:70000"},
       "--modbus-tcp = \"127.0.0.1:70000\", expected ADDR:PORT"},
      {{"--plant", "alatiqi4x4", "--modbus-tcp", "localhost"}, "--modbus-tcp = \"localhost\""},
      {{"--noise-var", "0.1"}, "--plant = (none), expected a plant"},
      {{"--plant", "nosuch"}, "plant.library = \"nosuch\", expected one of"},
  };
  for (const auto& [args, message] : cases) {
    const Refusal r = refused(args);
    EXPECT_EQ(r.exit_code, 2) << args.back();
    EXPECT_EQ(r.first_line, "") << args.back();
    EXPECT_THAT(r.stderr_text, HasSubstr(message));
  }
}

// Issue 19 item 4: before, each of these was served (--speedup 1e300 wrote 630 MB of log in
// 3 s). The wall-clock seconds per sample and the sample time in seconds lie within the
// gateway's tick periods (firmware/app/timing_range.hpp); the noise's standard deviation
// within what an output's register carries.
std::string text_of(double x) {  // as excite-plant prints numbers (ostream)
  std::ostringstream os;
  os << x;
  return os.str();
}

TEST(RobustBadInput, HugeTimingAndNoiseAreRefusedWithTheGatewaysRanges) {
  const std::string periods = "within the gateway's tick periods, " +
                              text_of(excite::app::kMinPeriodS) + " … " +
                              text_of(excite::app::kMaxPeriodS) + " s";
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
      {{"--plant", "woodberry2x2", "--clock", "realtime", "--speedup", "1e300"},
       "--speedup = 1e+300, expected a factor whose wall-clock seconds per sample"},
      {{"--plant", "woodberry2x2", "--clock", "realtime", "--speedup", "1e-300"},
       "--speedup = 1e-300, expected"},
      {{"--plant", "woodberry2x2", "--sample-time-min", "1e300"},
       "--sample-time-min = 1e+300, expected minutes whose seconds lie"},
      {{"--plant", "woodberry2x2", "--sample-time-s", "1e300"}, "--sample-time-s = 1e+300"},
      {{"--plant", "woodberry2x2", "--noise-var", "1e300"},
       "--noise-var = 1e+300, expected a variance whose standard deviation fits output y1's "
       "register"},
  };
  for (const auto& [args, message] : cases) {
    const Refusal r = refused(args);
    EXPECT_EQ(r.exit_code, 2) << args.back();
    EXPECT_EQ(r.first_line, "") << args.back();
    EXPECT_THAT(r.stderr_text, HasSubstr(message));
    if (message.find("noise") == std::string::npos) {
      EXPECT_THAT(r.stderr_text, HasSubstr(periods));
    }
  }
  // The ends of the range are served: one sample a day, and a large but representable noise.
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--plant", "woodberry2x2", "--sample-time-min", "1440"},
        std::vector<std::string>{"--plant", "woodberry2x2", "--noise-var", "1e30"}}) {
    TempDir dir;
    std::vector<std::string> a = args;
    a.insert(a.end(), {"--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep"});
    PlantRunner plant(a, dir.path() / "stderr.txt");
    EXPECT_TRUE(plant.wait_listening()) << plant.stderr_text();
    EXPECT_EQ(plant.stop(SIGTERM).value_or(-1), 0) << plant.stderr_text();
  }
}

}  // namespace
}  // namespace excite::sim::server
