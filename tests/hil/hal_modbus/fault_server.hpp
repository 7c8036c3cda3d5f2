// SPDX-License-Identifier: MIT
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

struct _modbus;
struct _modbus_mapping_t;

namespace excite::test {

// A real libmodbus TCP server on 127.0.0.1 in a thread, for tests and benchmarks:
// 65536 holding and 65536 input registers, one client at a time (a new connection
// replaces the old), every request recorded on the server side. It can be told to
// misbehave for the next n requests (STYLE.md practice 9):
//   stall      sleep `stall` before answering (the client times out)
//   drop       close the connection instead of answering (the client sees a reset)
//   exception  answer with exception 4, server device failure (transient)
//   refusal    answer with exception 3, illegal data value (the device refuses the request)
class FaultServer {
 public:
  enum class Fault { none, stall, drop, exception, refusal };

  struct Seen {  // one request as the server received it
    int function_code;
    int address;
    int count;
  };

  // port 0: an ephemeral port, see port().
  explicit FaultServer(std::uint16_t port = 0);
  ~FaultServer();
  FaultServer(const FaultServer&) = delete;
  FaultServer& operator=(const FaultServer&) = delete;

  [[nodiscard]] std::uint16_t port() const noexcept { return port_; }

  void inject(Fault fault, int requests = 1,
              std::chrono::milliseconds stall = std::chrono::milliseconds(200));

  void set_input(int address, std::uint16_t value);
  void set_holding(int address, std::uint16_t value);
  [[nodiscard]] std::uint16_t holding(int address);

  [[nodiscard]] std::vector<Seen> seen();
  [[nodiscard]] int count(int function_code);
  void clear_seen();

  // Stops serving and closes every socket (the port is free afterwards).
  void stop();

 private:
  void serve();

  _modbus* ctx_ = nullptr;
  _modbus_mapping_t* mapping_ = nullptr;
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::mutex mutex_;  // guards mapping_, seen_ and the fault settings
  std::vector<Seen> seen_;
  Fault fault_ = Fault::none;
  int fault_requests_ = 0;
  std::chrono::milliseconds stall_{200};
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace excite::test
