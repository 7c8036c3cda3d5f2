// SPDX-License-Identifier: MIT
#pragma once
// excite-plant over SocketCAN (`--can IFACE`): the plant as a CAN node with the default
// frame map (can_map.hpp). It takes the gateway's setpoint and heartbeat frames, advances the
// plant free-running or in lock-step (one sample per heartbeat change), and answers with
// its output frames, the readbacks of the setpoints it applies and the heartbeat echo, in
// that order; with nothing to answer it repeats them every `resend_ms` (a CAN node's cyclic
// transmission, so a gateway that starts later finds its values). The same guards as over
// Modbus (README, "Watchdog and input limits"): a heartbeat unchanged for watchdog_s
// returns the applied setpoints to the baseline until it moves; a setpoint frame with a
// value outside the input limits (or NaN) is refused as a whole — the plant keeps the last
// good setpoints, which its readback frames show — and counted, as are frames of a mapped
// identifier with too short a DLC. Frames of other identifiers are counted and ignored.

#include <linux/can.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hal/can/frame_map.hpp"
#include "sim/server/plant_log.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/plant_server.hpp"

namespace excite::sim::server {

class CanPlantServer {
 public:
  /// Opens and binds a raw CAN socket on `interface`, then the log (if any). Throws
  /// std::runtime_error naming what failed (no AF_CAN, no such interface, the log).
  /// Uses of `options`: lockstep, sample_period, log_path, plant_description, names and
  /// units, watchdog_s, input_min/input_max, faults.freeze_echo.
  CanPlantServer(PlantProcess& process, const hal::can::CanFrameMap& plant_map,
                 ServeOptions options, std::string interface, int resend_ms = 10);
  ~CanPlantServer();
  CanPlantServer(const CanPlantServer&) = delete;
  CanPlantServer& operator=(const CanPlantServer&) = delete;

  /// Serves until `stop()` returns true (checked at least every 50 ms). Throws
  /// std::runtime_error on a socket error. A failed log write (disk full, file-size limit)
  /// is not one: the log is cut back to its last whole row, logging stops, log_failure()
  /// says why, serving goes on.
  void run(const std::function<bool()>& stop);

  std::uint64_t frames_received() const { return frames_received_; }
  std::uint64_t frames_sent() const { return frames_sent_; }
  std::uint64_t wrong_dlc() const { return wrong_dlc_; }            // mapped id, too short
  std::uint64_t foreign_frames() const { return foreign_frames_; }  // ids not in the map
  std::uint64_t watchdog_trips() const { return watchdog_trips_; }
  std::uint64_t refused_frames() const { return refused_frames_; }  // input limits
  /// Why the run log stopped (PlantLog::failure()); "" when every sample was logged.
  const std::string& log_failure() const {
    static const std::string none;
    return log_ ? log_->failure() : none;
  }

 private:
  using Clock = std::chrono::steady_clock;
  void open_log();
  void receive(const can_frame& frame);
  void on_heartbeat(std::uint16_t heartbeat);
  void check_watchdog(Clock::time_point now);
  void take_sample();
  void send_answer();

  PlantProcess& process_;
  hal::can::CanPlan plan_;
  ServeOptions options_;
  std::string interface_;
  Clock::duration resend_;
  int fd_ = -1;

  std::vector<double> received_;  // decoded gateway signals: u_i..., heartbeat
  std::vector<double> written_;   // last accepted setpoints (absolute)
  std::vector<double> applied_;   // what the plant applies: written_, or u0 when tripped
  std::vector<double> y_;
  std::vector<double> answer_;  // y_j..., applied_i...
  std::vector<can_frame> tx_;
  std::uint16_t echo_ = 0;
  bool heartbeat_seen_ = false;
  std::uint16_t last_heartbeat_ = 0;
  Clock::time_point heartbeat_changed_at_;
  bool tripped_ = false;
  Clock::time_point last_sent_;

  std::uint64_t frames_received_ = 0;
  std::uint64_t frames_sent_ = 0;
  std::uint64_t wrong_dlc_ = 0;
  std::uint64_t foreign_frames_ = 0;
  std::uint64_t watchdog_trips_ = 0;
  std::uint64_t refused_frames_ = 0;
  std::uint64_t clamped_ = 0;

  std::optional<PlantLog> log_;  // the run log shared with the Modbus server (plant_log.hpp)
};

}  // namespace excite::sim::server

namespace excite::sim::server {

/// excite-plant's `--can IFACE`: builds the server on the default CAN frame map of the
/// process's plant, prints `listening can IFACE` on stdout (once frames can be received),
/// calls `ready()` (signal handlers), serves until `stop()`, and prints the summary on
/// stderr. Returns 0 when stopped, 1 when the interface or log could not be opened or
/// serving failed (the reason on stderr), 3 when stopped after its run log could not be
/// written (disk full, file-size limit: logging stopped, serving went on; said at once and
/// again at the stop), as excite-plant's exit codes.
int serve_can(PlantProcess& process, const ServeOptions& options, const std::string& interface,
              const std::function<void()>& ready, const std::function<bool()>& stop);

}  // namespace excite::sim::server
