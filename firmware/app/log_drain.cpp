// SPDX-License-Identifier: MIT
#include "firmware/app/log_drain.hpp"

#include <span>

#include "firmware/runlog/format.hpp"

namespace excite::app {

LogDrain::LogDrain(engine::LogRingBase& ring, std::FILE* file, LogLayout layout)
    : ring_(ring),
      file_(file),
      layout_(std::move(layout)),
      buffer_(runlog::max_row_chars(layout_.header.inputs.size(), layout_.header.outputs.size()) +
              4096),
      dy_(layout_.output_values.size()),
      writer_(file_, layout_.header, std::span<char>(buffer_)) {}

LogDrain::~LogDrain() {
  stop();
}

bool LogDrain::write_header() {
  const runlog::WriteStatus s = writer_.write_header();
  if (s != runlog::WriteStatus::ok) {
    error_ = s;
    return false;
  }
  return std::fflush(file_) == 0;
}

bool LogDrain::write(const engine::TickRecord& r) {
  const std::size_t n = layout_.header.inputs.size();
  for (std::size_t i = 0; i < dy_.size(); ++i) {
    dy_[i] = r.dy[static_cast<std::size_t>(layout_.output_values[i])];
  }
  runlog::Row row;
  row.t_min = static_cast<double>(r.tick) * layout_.header.sample_time_min;
  row.k = r.tick;
  row.du = std::span<const double>(r.du.data(), n);
  row.u = std::span<const double>(r.u.data(), n);
  row.dy = std::span<const double>(dy_);
  row.flags = r.flags & runlog::kKnownFlags;
  row.state = engine::to_run_state(r.state);
  const runlog::WriteStatus s = writer_.write_row(row);
  if (s != runlog::WriteStatus::ok) {
    error_ = s;
    return false;
  }
  // Every row goes to the file whole: even a SIGKILL leaves a log that ends on a complete
  // row (one write(2) of one row, never a stdio buffer cut mid-row).
  if (std::fflush(file_) != 0) {
    error_ = runlog::WriteStatus::io_error;
    return false;
  }
  rows_.fetch_add(1);
  return true;
}

void LogDrain::report(const engine::TickRecord& r) {
  if (events_ == nullptr) return;
  const double t = static_cast<double>(r.tick) * layout_.header.sample_time_min;
  if (r.state != last_state_) {
    std::fprintf(events_, "tick %llu (t = %g min, row %u): %s -> %s\n",
                 static_cast<unsigned long long>(r.tick), t, r.row, engine::to_string(last_state_),
                 engine::to_string(r.state));
    last_state_ = r.state;
  }
  const bool lost = (r.flags & runlog::kCommLost) != 0;
  if (lost != last_comm_lost_) {
    std::fprintf(events_, "tick %llu (t = %g min): %s\n", static_cast<unsigned long long>(r.tick),
                 t, lost ? "communication lost (flag comm_lost set)" : "communication restored");
    last_comm_lost_ = lost;
  }
}

bool LogDrain::drain_once() {
  engine::TickRecord record;
  bool any = false;
  while (ring_.pop(record)) {
    write(record);
    report(record);
    any = true;
    if (row_delay_.count() > 0) std::this_thread::sleep_for(row_delay_);
  }
  if (any) {
    std::fflush(file_);
    if (events_ != nullptr) std::fflush(events_);
  }
  return any;
}

void LogDrain::start() {
  stopping_ = false;
  finished_ = false;
  thread_.start([this] {
    while (!stopping_.load()) {
      if (!drain_once()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
}

void LogDrain::stop() {
  if (finished_) return;  // once: the caller may close the FILE after the first stop()
  finished_ = true;
  if (thread_.joinable()) {
    stopping_ = true;
    thread_.join();
  }
  drain_once();
  std::fflush(file_);
}

}  // namespace excite::app
