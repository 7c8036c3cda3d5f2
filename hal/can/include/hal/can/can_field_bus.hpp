// SPDX-License-Identifier: MIT
#pragma once

#include <linux/can.h>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/config/check.hpp"
#include "excite/hal/clock.hpp"
#include "excite/hal/field_bus.hpp"
#include "hal/can/frame_map.hpp"
#include "hal/can/link_state.hpp"

namespace excite::hal::can {

struct CanConfig {
  std::string interface = "can0";  // SocketCAN interface, e.g. can0, vcan0
  CanFrameMap map;
  std::int32_t value_timeout_ms = 100;  // a value frame older than this is stale, 1..60000
  std::uint32_t enobufs_limit = 10;     // consecutive write() calls with ENOBUFS = link loss
  std::uint32_t bitrate = 0;  // bit/s of a real bus (bus_timing.hpp); 0: virtual (vcan), unchecked
  // Lock-step with a simulated peer: index into map.values of the value carrying the peer's
  // heartbeat echo. read() after a write() then waits (poll, at most value_timeout_ms) until
  // that value equals the heartbeat written, so it returns the peer's answer to that write,
  // as a Modbus exchange does. Unset (the default): read() takes what is queued, never waits.
  std::optional<std::size_t> await_echo;
};

// What the socket transport counted since configure(), for the gateway's end-of-run summary
// (plain counters, updated in write()/read() without allocation).
struct CanCounters {
  std::uint64_t short_frames = 0;    // value frames with a DLC below what the map needs: refused,
  canid_t first_short_id = 0;        //   the values untouched; the first one's identifier
  std::uint8_t first_short_dlc = 0;  //   (flags stripped) and DLC
  std::uint64_t own_id_frames = 0;   // frames of one of the gateway's own setpoint identifiers:
  canid_t first_own_id = 0;          //   another node sends them (the socket never receives
                                     //   its own); ignored; the first one's identifier
  std::uint64_t send_failures = 0;   // write() calls in which a send failed (ENOBUFS: the
  int last_send_error = 0;           //   interface's queue is full); the last errno
  std::uint64_t stale_reads = 0;     // read() calls that found a value frame never received
                                     //   or older than value_timeout_ms (timeout)
  std::uint64_t echo_timeouts = 0;   // await_echo: reads without the heartbeat's echo in time
  std::uint64_t error_frames = 0;    // error frames received (LinkState)
};

// Checks the interface name, the timeouts and the frame map without opening a socket
// (what can be checked of a CAN configuration on a machine without AF_CAN).
config::Check validate(const CanConfig& config);

// Whether this kernel can open a SocketCAN raw socket. reason: "" when ok, else a
// static string naming the call and errno (e.g. EAFNOSUPPORT: no AF_CAN).
struct SocketCanSupport {
  StatusCode status;  // ok or unavailable
  const char* reason;
};
SocketCanSupport probe_socketcan() noexcept;

// The field bus over a SocketCAN raw socket. configure() compiles the frame map and
// opens the socket: receive filters for the value identifiers and for the gateway's own
// setpoint identifiers (another node sending them is counted: CanCounters::own_id_frames),
// all error frames enabled; every other identifier is dropped by the kernel, unseen.
// A value frame shorter than the map needs is refused and counted (short_frames).
// write(): one frame per setpoint identifier, non-blocking. read(): drains what the
// kernel queued, keeps the newest frame per identifier, and reports timeout (values
// untouched) while a value frame is missing or older than value_timeout_ms (with
// await_echo: first waits for the echo of the last write's heartbeat, timeout if none).
// Until a read has returned ok once (the gateway's read at arm), read() waits up to
// value_timeout_ms for every value frame to arrive: a peer's cyclic frames come on its own
// cycle, not in answer to a request as over Modbus. After that, a read never waits for them.
// Bus-off and persistent ENOBUFS are link_lost (see LinkState). On a kernel without AF_CAN,
// configure() fails naming the reason and every call returns unavailable.
// Time for staleness comes from the Clock given (the simulator may own it).
class CanFieldBus final : public FieldBus {
 public:
  explicit CanFieldBus(const Clock& clock) noexcept : clock_(clock) {}
  ~CanFieldBus() override;

  config::Check configure(const CanConfig& config);

  // The seam below the socket (STYLE.md practice 8): validates and compiles like
  // configure(), then uses `fd` — any open socket that carries one struct can_frame per
  // datagram, e.g. a raw socket set up elsewhere, or one end of a
  // socketpair(AF_UNIX, SOCK_SEQPACKET) playing the bus in tests. config.interface only
  // names it in messages. On success the bus owns fd (closes it); on failure the caller does.
  config::Check configure_on_socket(const CanConfig& config, int fd);

  StatusCode write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept override;
  StatusCode read(std::span<double> values) noexcept override;
  [[nodiscard]] std::size_t setpoint_count() const noexcept override {
    return plan_.setpoints.size();
  }
  [[nodiscard]] std::size_t value_count() const noexcept override { return plan_.values.size(); }
  [[nodiscard]] const char* detail() const noexcept override { return detail_; }

  [[nodiscard]] const LinkState& link() const noexcept { return link_; }
  [[nodiscard]] std::uint64_t clamped_setpoints() const noexcept { return clamped_; }
  [[nodiscard]] std::uint64_t short_frames() const noexcept { return counters_.short_frames; }
  [[nodiscard]] CanCounters counters() const noexcept {
    CanCounters c = counters_;
    c.error_frames = link_.error_frames();
    return c;
  }
  [[nodiscard]] const std::string& interface_name() const noexcept { return interface_; }

 private:
  void release() noexcept;
  bool drain() noexcept;  // receives what is queued; false (detail_ set) on a socket error
  StatusCode await_echo() noexcept;
  bool all_received() const noexcept;
  bool is_own_id(const can_frame& frame) const noexcept;  // one of the setpoint identifiers
  // Polls the socket, draining it, until `done()` or value_timeout_ms have passed.
  template <class Done>
  StatusCode wait_until(Done done) noexcept;
  config::Check prepare(const CanConfig& config, CanPlan& plan);
  void adopt(const CanConfig& config, CanPlan&& plan, int fd);

  const Clock& clock_;
  int fd_ = -1;
  CanPlan plan_;
  LinkState link_;
  std::vector<can_frame> tx_;
  std::vector<double> latest_;            // newest decoded values
  std::vector<Nanoseconds> received_at_;  // per rx frame; negative: never
  std::optional<std::size_t> await_echo_;
  std::optional<std::uint16_t> awaited_;  // heartbeat of the last write, until echoed
  bool had_values_ = false;               // a read has returned ok since configure
  Nanoseconds value_timeout_{0};
  std::string interface_;
  std::uint64_t clamped_ = 0;
  CanCounters counters_;
  char detail_[256] = "not configured";
};

}  // namespace excite::hal::can
