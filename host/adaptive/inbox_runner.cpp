// SPDX-License-Identifier: MIT
#include "host/adaptive/inbox_runner.hpp"

#include <signal.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>

#include "host/adaptive/growing_log.hpp"
#include "host/design/plan_file.hpp"

namespace excite::host {

namespace fs = std::filesystem;

InboxRunner::InboxRunner(InboxRunnerOptions options, InboxHooks hooks)
    : options_(std::move(options)), hooks_(std::move(hooks)) {
  std::error_code ec;
  if (!fs::is_directory(options_.inbox, ec)) {
    throw std::invalid_argument("inbox = " + options_.inbox.string() +
                                ", expected an existing folder (the gateway's --segment-inbox)");
  }
  if (!hooks_.start) {
    throw std::invalid_argument("hooks.start = none, expected a function that starts the gateway");
  }
  if (options_.segment_timeout.count() <= 0 || options_.poll.count() <= 0) {
    throw std::invalid_argument(
        "segment_timeout, poll = " + std::to_string(options_.segment_timeout.count()) + ", " +
        std::to_string(options_.poll.count()) + " ms, expected > 0");
  }
}

namespace {

constexpr const char* kMarker = "gateway.run";  // firmware/app run_identity.hpp

struct Marker {
  std::string run;  // 16 hexadecimal digits, "" when unreadable
  long pid = 0;
};

std::optional<Marker> read_marker(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  Marker m;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("run ", 0) == 0) m.run = line.substr(4);
    if (line.rfind("pid ", 0) == 0) m.pid = std::atol(line.c_str() + 4);
  }
  return m;
}

bool alive(long pid) {
  return pid > 0 && (kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

}  // namespace

std::string InboxRunner::check_gateway() {
  const fs::path path = options_.inbox / kMarker;
  const std::optional<Marker> m = read_marker(path);
  if (!m) {
    return run_id_.empty() ? std::string()  // not started yet
                           : path.string() + " = gone, expected the marker of run " + run_id_ +
                                 " (the gateway has ended)";
  }
  if (m->run.size() != 16 || m->pid <= 0) {
    return path.string() + " = unreadable, expected `run ID` and `pid PID` lines";
  }
  if (run_id_.empty()) {
    run_id_ = m->run;
    gateway_pid_ = m->pid;
    if (hooks_.attached) hooks_.attached(run_id_);
  } else if (m->run != run_id_) {
    return path.string() + ": run = " + m->run + ", expected " + run_id_ +
           " (another gateway run has started in this inbox)";
  }
  if (!alive(gateway_pid_)) {
    return "the gateway of run " + run_id_ + " (pid " + std::to_string(gateway_pid_) +
           ") is not running (" + path.string() + " left behind: killed?)";
  }
  return "";
}

// Segment k ≥ 1 into the inbox: a temporary file in the inbox renamed to next.plan (one
// rename: the gateway never reads a half-written plan), then approved.
void InboxRunner::hand_over(const plan::Plan& segment) {
  const fs::path next = options_.inbox / "next.plan";
  std::error_code ec;
  if (fs::exists(next, ec)) {
    throw std::runtime_error("segment " + std::to_string(next_) + ": " + next.string() +
                             " = present, expected absent (the gateway has not taken the last "
                             "segment)");
  }
  // The run it was decided for, in its provenance: the gateway refuses another run's segment
  // and pre-approves only its own.
  plan::Plan named = segment;
  const std::string provenance = "run " + run_id_ + ": " +
                                 std::string(plan::text_of(segment.meta.provenance));
  plan::set_text(named.meta.provenance, provenance.substr(0, plan::kProvenanceCapacity - 1));
  const fs::path tmp = options_.inbox / ".next.plan.tmp";
  fs::remove(tmp, ec);  // a link planted there is removed, never written through
  write_plan_file(named, tmp);
  fs::rename(tmp, next);
  handed_over_ = true;
  if (hooks_.approve) hooks_.approve(next_);
}

MeasuredSegment InboxRunner::run(const plan::Plan& segment) {
  handed_over_ = false;
  try {
    if (next_ == 0) {
      hooks_.start(segment);
    } else {
      if (const std::string why = check_gateway(); !why.empty() || run_id_.empty()) {
        throw std::runtime_error("segment " + std::to_string(next_) + ": " +
                                 (why.empty() ? "no gateway run found" : why));
      }
      hand_over(segment);
    }
    return wait_for_rows(segment);
  } catch (...) {
    // Stopped on an error: take back the segment it wrote, if the gateway has not taken it.
    std::error_code ec;
    if (handed_over_) fs::remove(options_.inbox / "next.plan", ec);
    throw;
  }
}

MeasuredSegment InboxRunner::wait_for_rows(const plan::Plan& segment) {
  const auto id = static_cast<std::uint32_t>(next_);
  const std::uint32_t rows = segment.recipe.samples;
  const std::string what = "segment " + std::to_string(id) + " (" + std::to_string(rows) +
                           " rows) in " + options_.run_log.string();
  const fs::path refused = options_.inbox / "next.plan.refused";
  const auto until = std::chrono::steady_clock::now() + options_.segment_timeout;
  SegmentSpan span;
  std::string stale;  // the producer of a log of another run, while one is seen
  for (;;) {
    // Asked before the log is read: a gateway that ended after writing every row is not
    // taken for one that ended without them.
    const std::string marker = check_gateway();  // finds the run on the first look
    std::string gone = hooks_.gone ? hooks_.gone() : std::string();
    if (gone.empty()) gone = marker;
    // Only a log of the run talked to: an earlier run's log is never taken for it.
    std::optional<runlog::RunLog> log;
    if (!run_id_.empty()) log = read_growing_log(options_.run_log);
    if (log && log->producer.find("run " + run_id_) == std::string::npos) {
      stale = log->producer;
      log.reset();
    }
    if (log) {
      if (log->input_names.size() != segment.recipe.channels) {
        throw std::runtime_error(
            options_.run_log.string() + ": inputs = " + std::to_string(log->input_names.size()) +
            ", expected " + std::to_string(segment.recipe.channels) + " (the segment's channels)");
      }
      span = find_segment(*log, id, consumed_, rows);
      if (!span.ended.empty()) throw std::runtime_error(what + ": " + span.ended);
      if (span.complete) {
        MeasuredSegment m;
        const auto n = static_cast<Eigen::Index>(span.end - consumed_);
        m.du.resize(n, static_cast<Eigen::Index>(log->du.size()));
        m.dy.resize(n, static_cast<Eigen::Index>(log->dy.size()));
        for (Eigen::Index i = 0; i < n; ++i) {
          const std::size_t r = consumed_ + static_cast<std::size_t>(i);
          for (std::size_t c = 0; c < log->du.size(); ++c)
            m.du(i, static_cast<Eigen::Index>(c)) = log->du[c][r];
          for (std::size_t j = 0; j < log->dy.size(); ++j)
            m.dy(i, static_cast<Eigen::Index>(j)) = log->dy[j][r];
        }
        consumed_ = span.end;
        ++next_;
        return m;
      }
    }
    std::error_code ec;
    if (id > 0 && fs::exists(refused, ec)) {
      throw std::runtime_error(what + ": the gateway refused it (" + refused.string() +
                               "; its stderr says why)");
    }
    if (!gone.empty()) {
      throw std::runtime_error(what + ": the gateway has stopped after " +
                               std::to_string(span.found) + " of its rows: " + gone);
    }
    if (std::chrono::steady_clock::now() > until) {
      if (run_id_.empty()) {
        throw std::runtime_error(what + ": no gateway run in " +
                                 (options_.inbox / kMarker).string() + " after " +
                                 std::to_string(options_.segment_timeout.count()) +
                                 " ms, expected one (was the gateway started with "
                                 "--segment-inbox " +
                                 options_.inbox.string() + "?)");
      }
      if (!stale.empty()) {
        throw std::runtime_error(options_.run_log.string() + ": producer = " + stale +
                                 ", expected the gateway run " + run_id_ +
                                 " (a log of another run)");
      }
      throw std::runtime_error(
          what + ": " + std::to_string(span.found) + " rows logged after " +
          std::to_string(options_.segment_timeout.count()) +
          " ms, expected all (is [segments] await_s > 0, and the segment approved?)");
    }
    std::this_thread::sleep_for(options_.poll);
  }
}

}  // namespace excite::host
