// SPDX-License-Identifier: MIT
#include "host/adaptive/inbox_runner.hpp"

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
  const fs::path tmp = options_.inbox / ".next.plan.tmp";
  write_plan_file(segment, tmp);
  fs::rename(tmp, next);
  if (hooks_.approve) hooks_.approve(next_);
}

MeasuredSegment InboxRunner::run(const plan::Plan& segment) {
  const auto id = static_cast<std::uint32_t>(next_);
  if (next_ == 0) {
    hooks_.start(segment);
  } else {
    hand_over(segment);
  }
  const std::uint32_t rows = segment.recipe.samples;
  const std::string what = "segment " + std::to_string(id) + " (" + std::to_string(rows) +
                           " rows) in " + options_.run_log.string();
  const fs::path refused = options_.inbox / "next.plan.refused";
  const auto until = std::chrono::steady_clock::now() + options_.segment_timeout;
  SegmentSpan span;
  for (;;) {
    // Asked before the log is read: a gateway that ended after writing every row is not
    // taken for one that ended without them.
    const std::string gone = hooks_.gone ? hooks_.gone() : std::string();
    const std::optional<runlog::RunLog> log = read_growing_log(options_.run_log);
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
      throw std::runtime_error(
          what + ": " + std::to_string(span.found) + " rows logged after " +
          std::to_string(options_.segment_timeout.count()) +
          " ms, expected all (is [segments] await_s > 0, and the segment approved?)");
    }
    std::this_thread::sleep_for(options_.poll);
  }
}

}  // namespace excite::host
