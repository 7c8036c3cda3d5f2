// SPDX-License-Identifier: MIT
#include "firmware/app/log_drain.hpp"

#include <span>

#include "firmware/runlog/format.hpp"

namespace excite::app {

LogDrain::LogDrain(engine::LogRingBase& ring, std::FILE* file, LogLayout layout)
    : ring_(ring),
      layout_(std::move(layout)),
      buffer_(runlog::max_closed_loop_row_chars(layout_.header.inputs.size(),
                                                layout_.header.outputs.size(),
                                                layout_.closed.r_channels.size()) +
              4096),
      dy_(layout_.output_values.size()),
      du_(layout_.header.inputs.size()),
      u_(layout_.header.inputs.size()),
      r_(layout_.closed.r_channels.size()),
      uc_(layout_.header.inputs.size()),
      ysp_(layout_.header.outputs.size()),
      st_(layout_.header.inputs.size()),
      file_rows_(fileno(file)) {
  // The header's r channels are the layout's own (a span: it points into layout_).
  layout_.header.closed_loop.r_channels = layout_.closed.r_channels;
}

LogDrain::~LogDrain() {
  stop();
}

void LogDrain::fail(int error, runlog::WriteStatus status, std::uint64_t tick) {
  errno_ = error;
  failed_tick_ = tick;
  error_ = status;
  failed_.store(true, std::memory_order_release);
  if (events_ != nullptr) {
    std::fprintf(events_,
                 "excite-gateway: fault: %s; stopping the excitation (ramp out to the "
                 "baseline, confirmed by readback)\n",
                 failure().c_str());
    std::fflush(events_);
  }
}

bool LogDrain::write_header() {
  const runlog::WriteResult f = runlog::format_header(layout_.header, std::span<char>(buffer_));
  if (f.status != runlog::WriteStatus::ok) {
    detail_ = f.message;
    failed_header_ = true;
    error_ = f.status;
    failed_.store(true);
    return false;
  }
  if (!file_rows_.append(std::span<const char>(buffer_.data(), f.length))) {
    failed_header_ = true;
    errno_ = file_rows_.error();
    error_ = runlog::WriteStatus::io_error;
    failed_.store(true);
    return false;
  }
  return true;
}

bool LogDrain::write(const engine::TickRecord& r) {
  if (failed_.load(std::memory_order_relaxed)) {
    lost_.fetch_add(1);
    return false;
  }
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
  row.segment = r.segment;
  if (layout_.header.closed_loop.closed) closed_loop_fields(r, row);
  const runlog::WriteResult f = runlog::format_row(layout_.header, row, std::span<char>(buffer_));
  if (f.status != runlog::WriteStatus::ok) {
    detail_ = f.message;
    fail(0, f.status, r.tick);
    lost_.fetch_add(1);
    return false;
  }
  if (max_bytes_ != 0 && file_rows_.whole_bytes() + f.length > max_bytes_) {
    limit_hit_ = true;
    fail(0, runlog::WriteStatus::capacity_exceeded, r.tick);
    lost_.fetch_add(1);
    return false;
  }
  // Every row goes to the file whole, in write(2) calls of its own: even a SIGKILL leaves a
  // log that ends on a complete row; a failed write leaves it cut back to one.
  if (!file_rows_.append(std::span<const char>(buffer_.data(), f.length))) {
    fail(file_rows_.error(), runlog::WriteStatus::io_error, r.tick);
    lost_.fetch_add(1);
    return false;
  }
  rows_.fetch_add(1);
  return true;
}

void LogDrain::closed_loop_fields(const engine::TickRecord& r, runlog::Row& row) {
  const std::size_t n = du_.size();
  for (std::size_t i = 0; i < n; ++i) {
    // What the plant got (README "Version 4": du_/u_ keep their open-loop meaning).
    du_[i] = r.du_applied[i];
    u_[i] = layout_.closed.mv_baseline[i] + r.du_applied[i];
    uc_[i] = r.uc[i];
    if (r.st[i] <= runlog::kMaxMvState) {
      st_[i] = static_cast<runlog::MvState>(r.st[i]);
    } else {
      st_[i] = runlog::MvState::manual;
      row.flags |= runlog::kBadValue;
    }
  }
  for (std::size_t k = 0; k < r_.size(); ++k) r_[k] = r.r[layout_.closed.r_source[k]];
  for (std::size_t j = 0; j < ysp_.size(); ++j) ysp_[j] = j < r.cvs ? r.ysp[j] : 0.0;
  if (r.mode <= static_cast<std::uint8_t>(runlog::LoopMode::suspended)) {
    row.mode = static_cast<runlog::LoopMode>(r.mode);
  } else {
    row.mode = runlog::LoopMode::off;
    row.flags |= runlog::kBadValue;
  }
  row.du = du_;
  row.u = u_;
  row.r = r_;
  row.uc = uc_;
  row.ysp = ysp_;
  row.st = st_;
}

std::string LogDrain::failure() const {
  if (!failed_.load()) return "";
  char why[192];
  if (limit_hit_) {
    std::snprintf(why, sizeof why, "it would pass gateway.log_max_mb = %g MB (%llu bytes)", max_mb_,
                  static_cast<unsigned long long>(max_bytes_));
  } else if (errno_ != 0) {
    runlog::describe_errno(errno_, why, sizeof why);
  } else {
    std::snprintf(why, sizeof why, "%s (%s)", std::string(runlog::describe(error_.load())).c_str(),
                  detail_);
  }
  if (failed_header_) return std::string("cannot write the run log's header: ") + why;
  char text[400];
  std::snprintf(text, sizeof text,
                "cannot write row %llu (tick %llu) of the run log: %s; the log is whole up to its "
                "last full row (%llu rows, %llu bytes)",
                static_cast<unsigned long long>(rows_.load() + 1),
                static_cast<unsigned long long>(failed_tick_), why,
                static_cast<unsigned long long>(rows_.load()),
                static_cast<unsigned long long>(file_rows_.whole_bytes()));
  return text;
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
  if (r.segment != last_segment_) {
    std::fprintf(events_, "tick %llu (t = %g min, row %u): segment %u -> %u\n",
                 static_cast<unsigned long long>(r.tick), t, r.row, last_segment_, r.segment);
    last_segment_ = r.segment;
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
  if (any && events_ != nullptr) std::fflush(events_);
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
}

}  // namespace excite::app
