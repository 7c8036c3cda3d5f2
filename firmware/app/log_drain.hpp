// SPDX-License-Identifier: MIT
#pragma once
// The non-real-time side of the run log: a thread pops TickRecords from the ring and writes
// them as run-log rows (firmware/runlog, the format `excite simulate` writes and
// `excite identify` reads), flushing the FILE after every row so an interrupted run (even
// SIGKILL) leaves a valid log up to its last drained tick. stop() drains what is left.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <thread>
#include <vector>

#include "firmware/app/small_thread.hpp"
#include "firmware/engine/log_ring.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::app {

struct LogLayout {
  runlog::Header header;           // names, units, producer, sample time (the plan's T,
                                   // minutes: t_min = tick · header.sample_time_min)
  std::vector<int> output_values;  // value index of each logged output, header order
};

class LogDrain {
 public:
  /// The FILE stays the caller's (open before, closed after stop()).
  LogDrain(engine::LogRingBase& ring, std::FILE* file, LogLayout layout);
  ~LogDrain();
  LogDrain(const LogDrain&) = delete;
  LogDrain& operator=(const LogDrain&) = delete;

  /// Writes the comment header and the column row; false on a write error (described()).
  bool write_header();

  void start();
  /// Drains everything pushed so far, flushes, joins the thread. Later calls (the
  /// destructor's) do nothing, so the caller may close the FILE after the first.
  void stop();

  /// Where state changes and comm-loss marks are reported as they are drained (one line
  /// each, e.g. "tick 120 (t = 120 min): running -> suspended [limit]"); null: silent.
  void set_event_stream(std::FILE* events) { events_ = events; }

  /// Test hook: sleep this long after each row (a slow disk).
  void set_row_delay(std::chrono::microseconds delay) { row_delay_ = delay; }

  [[nodiscard]] std::uint64_t rows_written() const { return rows_.load(); }
  [[nodiscard]] runlog::WriteStatus last_error() const { return error_.load(); }

 private:
  bool drain_once();  // pops until empty; true if any row was written
  bool write(const engine::TickRecord& r);
  void report(const engine::TickRecord& r);

  engine::LogRingBase& ring_;
  std::FILE* file_;
  LogLayout layout_;
  std::vector<char> buffer_;
  std::vector<double> dy_;
  runlog::FileWriter writer_;
  std::chrono::microseconds row_delay_{0};
  std::FILE* events_ = nullptr;
  engine::State last_state_ = engine::State::configured;
  bool last_comm_lost_ = false;
  std::atomic<bool> stopping_{false};
  bool finished_ = false;  // stop() has run since start()
  std::atomic<std::uint64_t> rows_{0};
  std::atomic<runlog::WriteStatus> error_{runlog::WriteStatus::ok};
  SmallThread thread_;
};

}  // namespace excite::app
