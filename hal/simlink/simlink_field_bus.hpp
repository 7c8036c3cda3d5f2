// SPDX-License-Identifier: MIT
#pragma once
// SimLinkFieldBus: the field bus as a simulated plant in the same process (STYLE.md
// practices 1 and 2). write() applies the setpoints and advances the plant one sample
// (sim::DiscretePlant, zero-order hold, time in minutes); read() returns what a PLC would
// report. Time is the caller's VirtualClock: each call may spend a fixed exchange time
// on it, so runs are deterministic and faster than real time.
//
// Values, in this order (value_count() of them):
//   [0, p)             plant outputs y0 + y(k) (+ an injected disturbance), absolute
//   [p, p + n)         readbacks: the setpoints the plant holds           (if readbacks)
//   next               heartbeat echo: the last heartbeat the plant received (if heartbeat_echo)
//   next               operator command register, set by the test        (if command_register)
//
// Faults on purpose (thread-safe setters, STYLE.md practice 9):
//   drop(n, status)        the next n calls of write() and read() fail with `status`
//                          (the plant keeps its time: a dropped write still advances it)
//   freeze_echo(true)      the heartbeat echo stops following the heartbeat (stale echo)
//   set_disturbance(j, d)  d is added to output j (a test-limit excursion)
//   set_command(code)      the command register's value

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "excite/hal/field_bus.hpp"
#include "excite/hal/virtual_clock.hpp"
#include "sim/lti/discrete_plant.hpp"
#include "sim/lti/transfer_matrix.hpp"

namespace excite::hal::simlink {

struct SimLinkConfig {
  std::vector<double> input_baseline;   // u0 per input, absolute: the plant's operating point
  std::vector<double> output_baseline;  // y0 per output, absolute
  bool readbacks = true;
  bool heartbeat_echo = true;
  bool command_register = false;
  Nanoseconds exchange_time{0};  // virtual time each write() and read() spends
};

class SimLinkFieldBus final : public FieldBus {
 public:
  /// Discretises g at sample_time_min (one plant sample per write). clock may be null
  /// (no time spent). Throws std::invalid_argument for baselines of the wrong size.
  SimLinkFieldBus(const sim::TransferMatrix& g, double sample_time_min, SimLinkConfig config,
                  VirtualClock* clock = nullptr);

  Status write(std::span<const double> setpoints, std::uint16_t heartbeat) noexcept override;
  Status read(std::span<double> values) noexcept override;
  [[nodiscard]] std::size_t setpoint_count() const noexcept override { return inputs_; }
  [[nodiscard]] std::size_t value_count() const noexcept override { return values_; }
  [[nodiscard]] const char* detail() const noexcept override { return detail_; }

  // Value indices (−1 when that value is not configured).
  [[nodiscard]] int readback_index(std::size_t input) const noexcept;
  [[nodiscard]] int heartbeat_echo_index() const noexcept { return echo_index_; }
  [[nodiscard]] int command_index() const noexcept { return command_index_; }

  // Fault injection and stimuli; safe from another thread.
  void drop(int calls, Status status = Status::timeout) noexcept;
  void freeze_echo(bool frozen) noexcept { echo_frozen_.store(frozen); }
  void set_disturbance(std::size_t output, double value) noexcept;
  void set_command(double code) noexcept { command_.store(code); }

  // What the plant saw.
  [[nodiscard]] std::uint64_t writes() const noexcept { return writes_.load(); }  // accepted
  [[nodiscard]] std::uint64_t reads() const noexcept { return reads_.load(); }    // answered
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(); }
  [[nodiscard]] std::uint64_t samples() const noexcept { return samples_.load(); }
  [[nodiscard]] double held_setpoint(std::size_t input) const noexcept { return held_[input]; }
  [[nodiscard]] std::uint16_t last_heartbeat() const noexcept { return heartbeat_.load(); }

 private:
  bool consume_drop(Status& status) noexcept;
  void spend_time() noexcept;

  sim::DiscretePlant plant_;
  SimLinkConfig config_;
  VirtualClock* clock_;
  std::size_t inputs_;
  std::size_t outputs_;
  std::size_t values_;
  int readback_base_ = -1;
  int echo_index_ = -1;
  int command_index_ = -1;

  std::vector<double> held_;  // setpoints held by the plant, absolute
  std::vector<double> du_;    // scratch: held − u0
  std::vector<double> y_;     // plant output deviations of the last sample
  std::vector<std::atomic<double>> disturbance_;
  std::atomic<std::uint16_t> heartbeat_{0};
  std::atomic<std::uint16_t> echo_{0};
  std::atomic<bool> echo_frozen_{false};
  std::atomic<double> command_{0.0};
  std::atomic<int> drop_calls_{0};
  std::atomic<Status> drop_status_{Status::timeout};
  std::atomic<std::uint64_t> writes_{0};
  std::atomic<std::uint64_t> reads_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> samples_{0};
  const char* detail_ = "";
};

}  // namespace excite::hal::simlink
