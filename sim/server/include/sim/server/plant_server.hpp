// SPDX-License-Identifier: MIT
#pragma once
// excite-plant's Modbus server (TCP, or RTU on a serial device): serves the register image,
// advances the plant in free-running (wall-clock) or lock-step time, misbehaves on purpose when
// told to, and logs every plant sample in the run-log format. Single-threaded and non-blocking: one
// poll loop assembles each connection's requests from whatever bytes have arrived, so no client
// (slow, half-open, stalled on purpose) delays another. Up to max_clients connections: a new
// one is always accepted; when full, the least recently active connection other than the
// gateway's (the last one that wrote the heartbeat) is closed. Idle and partial requests are
// bounded in time. Function codes 3, 4, 6 and 16 are served; any other is answered with
// exception 1 (illegal function), so no request bypasses the heartbeat bookkeeping. RTU: one
// master on the line, the same request handling, libmodbus framing and CRC.
// As a PLC would, it also guards itself (README, "Watchdog and input limits"): a heartbeat
// watchdog returns the setpoints to the baseline when the heartbeat stands still, and a
// setpoint write outside the input limits is refused with exception 3.

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sim/server/closed_loop.hpp"
#include "sim/server/controller_log.hpp"
#include "sim/server/modbus_request.hpp"
#include "sim/server/plant_log.hpp"
#include "sim/server/plant_process.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_layout.hpp"

struct _modbus;

namespace excite::sim::server {

/// Faults on purpose (STYLE.md practice 9). The counts apply to the following requests
/// that do not touch the control block, one fault per request, in the order drop,
/// exception, stall. Mirrored in the control block (README) when one is configured.
struct FaultSettings {
  std::uint16_t stall_ms = 0;            // how long a stalled request waits before its reply
  std::uint16_t stall_requests = 0;      // requests answered only after stall_ms
  std::uint16_t drop_requests = 0;       // requests answered by closing the connection
  std::uint16_t exception_requests = 0;  // requests answered with exception 4 (device failure)
  bool freeze_echo = false;              // the heartbeat echo stops following the heartbeat
};

struct ServeOptions {
  std::string host = "127.0.0.1";  // IPv4 address to listen on ("0.0.0.0": all)
  std::uint16_t port = 0;          // 0: an ephemeral port, see PlantServer::port()
  bool lockstep = false;           // one plant sample per heartbeat change
  std::chrono::duration<double> sample_period{1.0};  // free-running: wall-clock time per
                                                     // plant sample
  FaultSettings faults;                              // from the command line
  std::uint64_t faults_after = 0;  // ordinary requests served normally before faults apply
  // Frozen on purpose (as a SIGSTOP of the process, without the signal): after freeze_after
  // requests, nothing is read, answered or sampled for freeze_ms; then serving goes on with
  // whatever arrived meanwhile. 0: never.
  std::uint32_t freeze_ms = 0;
  std::uint64_t freeze_after = 0;
  std::string log_path;            // run log of every plant sample; empty: none
  std::string plant_description;   // the run log's `plant:` line
  runlog::TimeScales time_scales;  // the run log's τ_H, β (0: not known)
  std::vector<std::string> input_names;
  std::vector<std::string> output_names;
  std::vector<std::string> input_units;  // run-log units; empty: "-"
  std::vector<std::string> output_units;
  std::string rtu_device;  // non-empty: serve Modbus RTU on this serial device
  int rtu_baud = 19200;    // RTU: 8 data bits, no parity, 1 stop bit, unit 1
  int max_clients = 8;
  double idle_timeout_s = 60.0;    // a connection silent this long is closed (not the gateway's)
  double partial_timeout_s = 2.0;  // a request not complete this long after its first byte:
                                   // the connection is closed
  // The plant's own controller (README, "Watchdog and input limits"):
  double watchdog_s = 0.0;           // heartbeat unchanged this long (wall clock) after it first
                                     // changed: setpoints back to the baseline; 0: off
  std::vector<double> input_min;     // absolute limits per plant input; empty: none. A write
  std::vector<double> input_max;     // that would put a setpoint outside: exception 3, counted
  std::string controller_log_path;   // closed loop: the controller log (controller_log.hpp)
  std::vector<double> offset_limit;  // closed loop: |offset| bound per offset register (MV
                                     // offsets, then CV setpoint offsets); beyond: exception
                                     // 3, counted. Empty: none (ServerConfig plant.offset_limit)
};

/// The run log's settings in `options` (log_path, plant_description, time_scales, names and
/// units) with the plant's sample time: what every transport's server opens its log with.
PlantLogSpec plant_log_spec(const ServeOptions& options, double sample_time_min);

class PlantServer {
 public:
  /// Opens the log (if any) and listens. Throws std::runtime_error naming what failed.
  /// `loop`: the controller in the loop (README, "Closed loop"; the image's layout then has
  /// its registers); null: the open-loop plant, unchanged.
  PlantServer(PlantProcess& process, RegisterImage& image, ServeOptions options,
              ClosedLoop* loop = nullptr);
  ~PlantServer();
  PlantServer(const PlantServer&) = delete;
  PlantServer& operator=(const PlantServer&) = delete;

  std::uint16_t port() const { return port_; }

  /// Serves until `stop()` returns true (checked at least every 50 ms), then closes every
  /// connection. Throws std::runtime_error on a socket error it cannot recover from. A failed
  /// log write (disk full, file-size limit) is not one: the log is cut back to its last whole
  /// row, logging stops, log_failure() says why, serving goes on.
  void run(const std::function<bool()>& stop);

  std::uint64_t requests() const { return requests_; }
  /// Requests answered with exception 1 (function code not served).
  std::uint64_t illegal_functions() const { return illegal_functions_; }
  /// Connections closed by the server: malformed frames, idle, partial, evicted.
  std::uint64_t closed_connections() const { return closed_connections_; }
  /// RTU: frames dropped for a bad CRC or garbage on the line.
  std::uint64_t rejected_frames() const { return rejected_frames_; }
  /// RTU: times the serial line went away (hang-up, I/O error); each said on stderr, then
  /// the device reopened every 0.5 s until it is back (issue 39 §4: no spinning).
  std::uint64_t line_losses() const { return line_losses_; }
  /// Times the watchdog returned the setpoints to the baseline (control block +6).
  std::uint64_t watchdog_trips() const { return watchdog_trips_; }
  /// Setpoint writes refused for the input limits (exception 3; control block +7); under a
  /// controller also writes to the setpoint registers (exception 2: the controller's).
  std::uint64_t refused_writes() const { return refused_writes_; }
  /// Why the controller log stopped; "" when it is whole (or there is none).
  std::string controller_log_failure() const {
    return controller_log_ ? controller_log_->failure() : std::string();
  }
  /// Why the run log stopped ("--log plant.csv: cannot write sample 412: No space left on
  /// device (ENOSPC); …"); "" when every sample was logged.
  const std::string& log_failure() const {
    static const std::string none;
    return log_ ? log_->failure() : none;
  }

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kMaxAdu = 260;  // Modbus TCP: 7-byte MBAP + 253-byte PDU

  struct Client {
    int fd = -1;
    std::array<std::uint8_t, kMaxAdu> frame{};
    std::size_t have = 0;                       // bytes of the request being assembled
    Clock::time_point last_activity;            // last byte received (or accepted)
    Clock::time_point request_started;          // first byte of the request being assembled
    std::optional<Clock::time_point> reply_at;  // a stalled request, answered then
    bool gateway = false;                       // the last connection that wrote the heartbeat
  };

  void listen();
  void open_log();
  void release();
  void accept_client();
  void close_client(std::size_t index);
  void receive(std::size_t index);
  enum class Outcome { replied, close, drop, stall };
  // One complete request (ADU of `length` bytes; the reply goes out on ctx_'s current
  // socket): function-code and length checks, faults, the reply, the write bookkeeping.
  Outcome handle(std::uint8_t* query, int length, bool stall_done, bool& heartbeat_written);
  void answer(std::size_t index, bool stall_done);
  bool rtu() const { return !options_.rtu_device.empty(); }
  void serve_rtu(const std::function<bool()>& stop);
  void lose_line(const char* why);
  void wait_for_line(const std::function<bool()>& stop);
  void check_deadlines(Clock::time_point now);
  bool touches_control(const ModbusRequest& request) const;
  void on_heartbeat_written();
  // A write of setpoints outside the limits: counted, reported, true (the caller refuses).
  bool refuse_out_of_limits(const ModbusRequest& request, const std::uint8_t* data);
  // Under a controller: a write of a test offset beyond plant.offset_limit, the same way.
  bool refuse_offset_beyond_limit(std::uint32_t address, std::uint32_t count,
                                  const std::uint8_t* data);
  void check_watchdog(Clock::time_point now);
  void freeze(const std::function<bool()>& stop);
  void mirror_counters_to_control();
  void take_sample();
  void take_closed_loop_sample();
  void report_misfits(std::uint64_t k);
  void load_faults_from_control();
  void mirror_faults_to_control();
  bool faults_armed() const { return ordinary_requests_ >= options_.faults_after; }

  PlantProcess& process_;
  RegisterImage& image_;
  ServeOptions options_;
  _modbus* ctx_ = nullptr;
  int listen_fd_ = -1;
  std::uint16_t port_ = 0;
  std::vector<Client> clients_;  // oldest first
  std::uint64_t illegal_functions_ = 0;
  std::uint64_t closed_connections_ = 0;
  std::uint64_t rejected_frames_ = 0;
  std::uint64_t line_losses_ = 0;
  bool line_lost_ = false;  // RTU: the serial line went away; reopened every 0.5 s
  std::vector<std::uint64_t> misfits_reported_;  // per output: count when last reported

  FaultSettings faults_;
  std::uint64_t requests_ = 0;
  std::uint64_t ordinary_requests_ = 0;  // requests that do not touch the control block
  bool heartbeat_seen_ = false;
  std::uint16_t last_heartbeat_ = 0;

  Clock::time_point heartbeat_changed_at_;  // wall clock of the last heartbeat change
  bool watchdog_tripped_ = false;           // setpoints held at the baseline
  std::vector<std::uint16_t> pending_;      // setpoints written while tripped: applied when
  bool has_pending_ = false;                // the heartbeat moves again
  std::uint64_t watchdog_trips_ = 0;
  std::uint64_t refused_writes_ = 0;
  bool frozen_ = false;  // the freeze on purpose has happened

  std::vector<double> u_;
  std::vector<double> y_;

  ClosedLoop* loop_ = nullptr;  // closed loop: the controller (not owned)
  std::vector<double> mv_offsets_;
  std::vector<double> sp_offsets_;
  std::vector<double> y_measured_;  // the CVs of the last sample, deviations (with noise)
  std::vector<std::uint16_t> status_;
  std::optional<ControllerLog> controller_log_;

  std::optional<PlantLog> log_;  // the run log (plant_log.hpp); empty until opened
};

/// excite-plant over Modbus (TCP, or RTU with options.rtu_device): builds the server on
/// `image` (laid out by `layout`), calls `ready()` (signal handlers), prints `listening
/// HOST:PORT` (RTU: `listening DEVICE:BAUD`) on stdout and the plant on stderr
/// (`default_map`: the map derived from the plant, no --config), serves until `stop()`,
/// and prints the summary on stderr: the counts, the outputs that did not fit their
/// registers, a log failure. Returns excite-plant's exit code: 0 stopped, 1 when it could
/// not listen or open the log, or serving failed (the reason on stderr), 3 stopped after
/// its run log could not be written (as serve_can).
int serve_modbus(PlantProcess& process, RegisterImage& image, const ServerLayout& layout,
                 const ServeOptions& options, bool default_map, const std::function<void()>& ready,
                 const std::function<bool()>& stop, ClosedLoop* loop = nullptr);

}  // namespace excite::sim::server
