// SPDX-License-Identifier: MIT
#pragma once
// The loop over SocketCAN (label can-vm): the real excite-plant --can and the real
// excite-gateway on a vcan bus, configured by `excite loop-config --transport can`, and a raw
// socket beside them that reads what they send (BusObserver). Shared by the CAN loop tests.
#include <linux/can.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "../hal_can/vcan_required.hpp"
#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {

using namespace std::chrono_literals;

inline constexpr const char* kBus = "vcan0";

// A raw socket on the bus, beside the gateway and the plant: reads what they send.
using Clock = std::chrono::steady_clock;

class BusObserver {
 public:
  explicit BusObserver(const char* bus = kBus) {
    fd_ = socket(PF_CAN, SOCK_RAW, CAN_RAW);
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(if_nametoindex(bus));
    ok_ = fd_ >= 0 && bind(fd_, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  }
  ~BusObserver() {
    if (fd_ >= 0) close(fd_);
  }
  BusObserver(const BusObserver&) = delete;
  BusObserver& operator=(const BusObserver&) = delete;
  bool ok() const { return ok_; }

  // The newest frame of each identifier received within `window`.
  std::map<canid_t, can_frame> collect(std::chrono::milliseconds window) {
    std::map<canid_t, can_frame> newest;
    const auto end = Clock::now() + window;
    while (Clock::now() < end) {
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 5) != 1) continue;
      can_frame f{};
      if (::read(fd_, &f, sizeof f) == static_cast<ssize_t>(sizeof f)) newest[f.can_id] = f;
    }
    return newest;
  }

 private:
  int fd_ = -1;
  bool ok_ = false;
};

inline float float_at(const can_frame& f, int offset) {
  float x = 0.0F;
  std::memcpy(&x, f.data + offset, sizeof x);  // little-endian, as the host
  return x;
}

// "200#0000803F00000040": a cansend frame of identifier `id` carrying `values` as float32.
inline std::string float_frame(unsigned id, std::initializer_list<float> values) {
  char head[16];
  std::snprintf(head, sizeof head, "%03X#", id);
  std::string text = head;
  for (float v : values) {
    unsigned char bytes[4];
    std::memcpy(bytes, &v, 4);
    for (unsigned char b : bytes) {
      char hex[3];
      std::snprintf(hex, sizeof hex, "%02X", b);
      text += hex;
    }
  }
  return text;
}

// The number after `label` in the gateway's end-of-run CAN counts ("excite-gateway: can vcan0:
// value frames refused for their DLC N …, reads with a value frame stale or missing N, …");
// -1 when absent.
inline long can_count(const std::string& err, const std::string& label) {
  const std::size_t line = err.find("excite-gateway: can ");
  if (line == std::string::npos) return -1;
  const std::size_t at = err.find(label + " ", line);
  if (at == std::string::npos || at > err.find('\n', line)) return -1;
  return std::stol(err.substr(at + label.size() + 1));
}

// The loop over a vcan bus: the plant from loop-config's plant.toml, the gateway from its
// gateway.toml (LoopTest::start_gateway).
class CanLoop : public LoopTest {
 protected:
  // Waits until the plant has logged more than `samples` samples.
  bool wait_for_plant_samples(const std::string& log, std::size_t samples) {
    for (const auto until = Clock::now() + 30s; Clock::now() < until;) {
      std::size_t lines = 0;
      std::ifstream in(path(log));
      for (std::string line; std::getline(in, line);) {
        lines += line.empty() || line[0] == '#' ? 0U : 1U;
      }
      if (lines > samples) return true;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }

  // gateway.toml for a real-time gateway (5 ms ticks): the plant's readbacks answer a write
  // a tick or more later (frames are not replies), so they are compared with the write 3
  // ticks back; a dead peer's last frames stay fresh for value_timeout_ms (100 ms here),
  // its readbacks frozen meanwhile: the mismatch limit (100 ticks, 0.5 s) lets the frames
  // go stale first, and leaves room for qemu TCG on a loaded machine.
  void real_time_gateway() {
    std::ifstream in(path("gateway.toml"));
    std::ostringstream text;
    text << in.rdbuf();
    std::string t = text.str();
    t.replace(t.find("value_timeout_ms = 1000"), 23, "value_timeout_ms = 100");
    t.replace(t.find("[gateway]\n"), 10,
              "[gateway]\nreadback_lag_ticks = 4\nreadback_mismatch_limit = 100\n");
    std::ofstream(path("gateway.toml")) << t;
  }

  // loop-config --transport can, then excite-plant --config plant.toml --can BUS ARGS
  // (`program` in front: e.g. prlimit and its options, then excite-plant; empty: none).
  void start_can_loop(const std::string& plant, const std::string& config_args,
                      const std::vector<std::string>& plant_args, const char* bus = kBus,
                      const std::vector<std::string>& program = {}) {
    loop_config(plant, 1502, "--transport can --interface " + std::string(bus) + " " + config_args);
    std::vector<std::string> args = {"--config", path("plant.toml").string(), "--can", bus,
                                     "--log",    path("plant.csv").string()};
    args.insert(args.end(), plant_args.begin(), plant_args.end());
    if (program.empty()) {
      plant_ = std::make_unique<PlantRunner>(args, path("plant.stderr"));
    } else {
      std::vector<std::string> line(program.begin() + 1, program.end());
      line.insert(line.end(), args.begin(), args.end());
      plant_ = std::make_unique<PlantRunner>(program.front(), line, path("plant.stderr"));
    }
    plant_->wait_listening();
    ASSERT_EQ(plant_->first_line(), "listening can " + std::string(bus)) << plant_->stderr_text();
  }
};

}  // namespace excite::test
