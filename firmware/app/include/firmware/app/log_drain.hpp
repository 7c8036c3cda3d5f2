// SPDX-License-Identifier: MIT
#pragma once
// The non-real-time side of the run log: a thread pops TickRecords from the ring and writes
// them as run-log rows (firmware/runlog, the format `excite simulate` writes and
// `excite identify` reads), each row in write(2) calls of its own (runlog::RowFile, no stdio
// buffer) so an interrupted run (even SIGKILL) leaves a valid log up to its last drained
// tick. stop() drains what is left.
//
// A failed or short write (disk full, file-size limit, I/O error) is a fault, not a death
// (issue 19): the file is cut back to its last whole row, failed() is raised for the tick
// loop (Runner::watch_log: the excitation stops, ramps out, the baseline is confirmed), the
// reason is reported once on the event stream, and the thread keeps draining the ring
// without writing, so state changes are still reported and the ring never overruns.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "firmware/app/closed_loop_log.hpp"
#include "firmware/app/small_thread.hpp"
#include "firmware/engine/log_ring.hpp"
#include "firmware/runlog/row_file.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::app {

struct LogLayout {
  runlog::Header header;           // names, units, producer, sample time (the plan's T,
                                   // minutes: t_min = tick · header.sample_time_min)
  std::vector<int> output_values;  // value index of each logged output, header order
  // Closed loop (header.closed_loop.closed, run-log v4): the r mapping and the MVs'
  // operating points; the header's inputs are the MVs and du_/u_ what the plant got.
  ClosedLoopLogLayout closed;
};

class LogDrain {
 public:
  /// The FILE stays the caller's (open before, closed after stop()).
  LogDrain(engine::LogRingBase& ring, std::FILE* file, LogLayout layout);
  ~LogDrain();
  LogDrain(const LogDrain&) = delete;
  LogDrain& operator=(const LogDrain&) = delete;

  /// Writes the comment header and the column row; false on a write error (failure()).
  bool write_header();

  void start();
  /// Drains everything pushed so far, flushes, joins the thread. Later calls (the
  /// destructor's) do nothing, so the caller may close the FILE after the first.
  void stop();

  /// Where state changes and comm-loss marks are reported as they are drained (one line
  /// each, e.g. "tick 120 (t = 120 min): running -> suspended [limit]"); null: silent.
  void set_event_stream(std::FILE* events) { events_ = events; }

  /// The log's size limit in bytes: a row that would pass it is a failed write (failure()
  /// names the limit), as a full disk. 0: none.
  void set_max_bytes(std::uint64_t bytes, double as_mb) {
    max_bytes_ = bytes;
    max_mb_ = as_mb;
  }

  /// Test hook: sleep this long after each row (a slow disk).
  void set_row_delay(std::chrono::microseconds delay) { row_delay_ = delay; }

  [[nodiscard]] std::uint64_t rows_written() const { return rows_.load(); }
  [[nodiscard]] runlog::WriteStatus last_error() const { return error_.load(); }

  /// Raised (once, never lowered) when a write failed: the tick loop polls it.
  [[nodiscard]] const std::atomic<bool>& failed() const { return failed_; }
  /// Why, after failed() (read it once the thread was stopped): "cannot write the header:
  /// No space left on device (ENOSPC)" or "cannot write row 412 (tick 411): File too large
  /// (EFBIG); the log is whole up to its last full row (411 rows, 52311 bytes)"; "" if none.
  [[nodiscard]] std::string failure() const;
  /// Records drained after the failure and not written (the log's missing ticks).
  [[nodiscard]] std::uint64_t rows_lost() const { return lost_.load(); }

 private:
  bool drain_once();  // pops until empty; true if any row was written
  bool write(const engine::TickRecord& r);
  // A v4 row's closed-loop fields from the record (the applied MVs as du/u); an MV status or
  // mode out of range is written as manual / off with kBadValue set in `flags`.
  void closed_loop_fields(const engine::TickRecord& r, runlog::Row& row);
  void report(const engine::TickRecord& r);
  void fail(int error, runlog::WriteStatus status, std::uint64_t tick);

  engine::LogRingBase& ring_;
  LogLayout layout_;
  std::vector<char> buffer_;
  std::vector<double> dy_;
  // v4 rows (closed loop), sized once: du/u applied, r, uc, ysp, statuses.
  std::vector<double> du_, u_, r_, uc_, ysp_;
  std::vector<runlog::MvState> st_;
  runlog::RowFile file_rows_;
  std::chrono::microseconds row_delay_{0};
  std::FILE* events_ = nullptr;
  engine::State last_state_ = engine::State::configured;
  std::uint32_t last_segment_ = 0;  // plan segment of the last row reported
  bool last_comm_lost_ = false;
  std::atomic<bool> stopping_{false};
  bool finished_ = false;  // stop() has run since start()
  std::atomic<std::uint64_t> rows_{0};
  std::atomic<runlog::WriteStatus> error_{runlog::WriteStatus::ok};
  std::atomic<bool> failed_{false};
  std::atomic<std::uint64_t> lost_{0};
  std::uint64_t max_bytes_ = 0;
  double max_mb_ = 0.0;
  bool limit_hit_ = false;         // the failure is the size limit
  int errno_ = 0;                  // of the failed write (0: a formatting refusal)
  bool failed_header_ = false;     // the header was what failed
  std::uint64_t failed_tick_ = 0;  // the tick whose row could not be written
  const char* detail_ = "";        // a formatting refusal's text
  SmallThread thread_;
};

}  // namespace excite::app
