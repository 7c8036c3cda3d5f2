// SPDX-License-Identifier: MIT
#pragma once
// SimLinkFieldBus: the field bus as a simulated plant in the same process (STYLE.md
// practices 1 and 2). Any sim::Plant — a linear model, a plant file, the nonlinear columns —
// driven through its live interface: reset(T) at construction, then write() applies the
// setpoints and advances the plant one sample (Plant::step, zero-order hold, time in
// minutes); read() returns what a PLC would report. Time is the caller's VirtualClock: each
// call may spend a fixed exchange time on it, so runs are deterministic and faster than
// real time.
//
// Values, in this order (value_count() of them):
//   [0, p)             plant outputs y0 + dy(k) (+ an injected disturbance), absolute
//   [p, p + n)         readbacks: the setpoints the plant holds           (if readbacks)
//   next               heartbeat echo: the last heartbeat the plant received (if heartbeat_echo)
//   next               operator command register, set by the test        (if command_register;
//                      the one value write_value writes: the gateway's acknowledgement)
//
// Faults on purpose (thread-safe setters, STYLE.md practice 9):
//   drop(n, status)        the next n calls of write() and read() fail with `status`
//                          (the plant keeps its time: a dropped write still advances it)
//   freeze_echo(true)      the heartbeat echo stops following the heartbeat (stale echo)
//   set_disturbance(j, d)  d is added to output j (a test-limit excursion)
//   set_command(code)      the command register's value
// A plant that refuses a sample (a column drained by its inputs, or over its work cap)
// makes write() return peer_error with the plant's message in detail(); that sample does
// not happen.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "excite/hal/field_bus.hpp"
#include "excite/hal/virtual_clock.hpp"
#include "sim/lti/transfer_matrix.hpp"
#include "sim/plants/plant.hpp"

namespace excite::sim::simlink {

struct SimLinkConfig {
  // Absolute operating point: u0 per input, y0 per output. Empty: the plant's own
  // (Plant::input_baseline(), output_baseline(); zero for the linear models).
  std::vector<double> input_baseline;
  std::vector<double> output_baseline;
  bool readbacks = true;
  bool heartbeat_echo = true;
  bool command_register = false;
  hal::Nanoseconds exchange_time{0};  // virtual time each write() and read() spends
};

class SimLinkFieldBus final : public hal::FieldBus {
 public:
  /// Drives `plant` live, one sample of sample_time_min minutes per write (calls
  /// plant->reset(sample_time_min) now). clock may be null (no time spent). Throws
  /// std::invalid_argument for a null plant, a bad sample time or baselines of the wrong size.
  SimLinkFieldBus(std::unique_ptr<Plant> plant, double sample_time_min, SimLinkConfig config,
                  hal::VirtualClock* clock = nullptr);
  /// A linear plant given by its transfer matrix g.
  SimLinkFieldBus(const TransferMatrix& g, double sample_time_min, SimLinkConfig config,
                  hal::VirtualClock* clock = nullptr);

  hal::StatusCode write(std::span<const double> setpoints,
                        std::uint16_t heartbeat) noexcept override;
  hal::StatusCode read(std::span<double> values) noexcept override;
  // The command register is the one value written back (the gateway's acknowledgement,
  // `acknowledge = "clear"`); any other value: unavailable.
  hal::StatusCode write_value(std::size_t index, double value) noexcept override;
  [[nodiscard]] bool value_writable(std::size_t index) const noexcept override {
    return command_index_ >= 0 && index == static_cast<std::size_t>(command_index_);
  }
  [[nodiscard]] std::size_t setpoint_count() const noexcept override { return inputs_; }
  [[nodiscard]] std::size_t value_count() const noexcept override { return values_; }
  [[nodiscard]] const char* detail() const noexcept override { return detail_; }

  // Value indices (−1 when that value is not configured).
  [[nodiscard]] int readback_index(std::size_t input) const noexcept;
  [[nodiscard]] int heartbeat_echo_index() const noexcept { return echo_index_; }
  [[nodiscard]] int command_index() const noexcept { return command_index_; }

  // Fault injection and stimuli; safe from another thread.
  void drop(int calls, hal::StatusCode status = hal::StatusCode::timeout) noexcept;
  void freeze_echo(bool frozen) noexcept { echo_frozen_.store(frozen); }
  void set_disturbance(std::size_t output, double value) noexcept;
  void set_command(double code) noexcept { command_.store(code); }

  // What the plant saw.
  [[nodiscard]] std::uint64_t writes() const noexcept { return writes_.load(); }  // accepted
  [[nodiscard]] std::uint64_t reads() const noexcept { return reads_.load(); }    // answered
  [[nodiscard]] std::uint64_t dropped() const noexcept { return dropped_.load(); }
  [[nodiscard]] std::uint64_t samples() const noexcept { return samples_.load(); }
  [[nodiscard]] std::uint64_t plant_errors() const noexcept { return plant_errors_.load(); }
  [[nodiscard]] double held_setpoint(std::size_t input) const noexcept { return held_[input]; }
  [[nodiscard]] std::uint16_t last_heartbeat() const noexcept { return heartbeat_.load(); }
  /// The plant (not thread-safe: only between calls of write()).
  [[nodiscard]] const Plant& plant() const noexcept { return *plant_; }

 private:
  bool consume_drop(hal::StatusCode& status) noexcept;
  void spend_time() noexcept;

  std::unique_ptr<Plant> plant_;
  SimLinkConfig config_;
  hal::VirtualClock* clock_;
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
  std::atomic<hal::StatusCode> drop_status_{hal::StatusCode::timeout};
  std::atomic<std::uint64_t> writes_{0};
  std::atomic<std::uint64_t> reads_{0};
  std::atomic<std::uint64_t> dropped_{0};
  std::atomic<std::uint64_t> samples_{0};
  std::atomic<std::uint64_t> plant_errors_{0};
  const char* detail_ = "";
  char plant_error_[160] = {};  // the plant's last refusal, for detail()
};

}  // namespace excite::sim::simlink
