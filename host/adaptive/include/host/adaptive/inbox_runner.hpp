// SPDX-License-Identifier: MIT
#pragma once
// The adaptive test through a running excite-gateway (issue 26 §4): each segment goes into
// the gateway's --segment-inbox, and what the plant did is read back from the gateway's run
// log as it grows (firmware/app/README.md, "Plan segments"; host/adaptive/README.md,
// "Through the gateway").
//
//   call 0:   hooks.start(plan)  — the caller starts the gateway with segment 0 as its --plan
//             (segment 0 is decided inside run_adaptive_test, so the runner hands it over);
//   call k≥1: the plan written to DIR/next.plan atomically (a temporary file in DIR renamed),
//             then hooks.approve(k) (stdin `approve`, or nothing with [segments]
//             preapproved_from);
//   then:     the run log polled until it holds every table row of segment k; those rows
//             returned, with any rows logged since the last call before them.
//
// The gateway run (issue 39 §3): the runner talks to the gateway run named in
// DIR/gateway.run (firmware/app run_identity.hpp: its run id, pid and log), which the gateway
// writes at start and removes at exit. It reads only a run log whose producer line names that
// run (a stale log of an earlier run is never taken for this one), writes that run into every
// segment's provenance (`run ID: excite test segment …`: the gateway refuses another run's
// segment and pre-approves only its own), reports the gateway gone as soon as that pid is,
// and takes back a next.plan it wrote when it stops on an error (nothing a later gateway
// would take is left behind).
//
// The gateway must await each next segment at its table's end ([segments] await_s > 0),
// since segment k + 1 is decided only after segment k's data. In lock-step it stops ticking
// meanwhile, so the record is the segments back to back, as in process. In real time it holds
// the baseline and logs those rows (flagged suspended): they belong to the record, and come
// back at the front of the next segment's rows (MeasuredSegment::du has more rows than the
// segment's table then; AdaptiveResult::U stays one contiguous record).

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "host/adaptive/adaptive_test.hpp"

namespace excite::host {

struct InboxRunnerOptions {
  std::filesystem::path inbox;                        // the gateway's --segment-inbox DIR (exists)
  std::filesystem::path run_log;                      // the gateway's --log FILE
  std::chrono::milliseconds segment_timeout{60'000};  // longest wait for one segment's rows
  std::chrono::milliseconds poll{10};                 // between reads of the run log
};

struct InboxHooks {
  /// Call 0: start the gateway streaming `first` (write it as its --plan). Required.
  std::function<void(const plan::Plan& first)> start;
  /// Call k ≥ 1, after DIR/next.plan is in place: approve segment k. Empty: pre-approved.
  std::function<void(int segment)> approve;
  /// "" while the gateway runs; else how it ended (exit code, the end of its stderr). Empty:
  /// not watched (the timeout still applies; the marker's pid is watched either way).
  std::function<std::string()> gone;
  /// Once, when the gateway's run is found (DIR/gateway.run): its run id. Optional.
  std::function<void(const std::string& run)> attached;
};

class InboxRunner final : public SegmentRunner {
 public:
  /// Throws std::invalid_argument when the inbox is not a folder, a hook required is
  /// missing, or a duration is not positive.
  InboxRunner(InboxRunnerOptions options, InboxHooks hooks);

  /// Throws std::runtime_error naming the segment and what was seen: the gateway refused the
  /// segment (next.plan.refused), a segment is still waiting in the inbox, the gateway has
  /// gone, the run ended or moved on without the segment's rows, the log is not a valid run
  /// log or has other channels than the plan, or the timeout passed.
  MeasuredSegment run(const plan::Plan& segment) override;

  /// Rows of the run log returned so far (the next call's rows start there).
  [[nodiscard]] std::size_t rows_returned() const noexcept { return consumed_; }
  /// The gateway run talked to ("" until found).
  [[nodiscard]] const std::string& run_id() const noexcept { return run_id_; }

 private:
  void hand_over(const plan::Plan& segment);
  MeasuredSegment wait_for_rows(const plan::Plan& segment);
  // "" while the run named in DIR/gateway.run is the one talked to and its pid lives; else
  // why not. Finds the run on the first call that sees the marker.
  std::string check_gateway();

  InboxRunnerOptions options_;
  InboxHooks hooks_;
  int next_ = 0;
  std::size_t consumed_ = 0;
  std::string run_id_;
  long gateway_pid_ = 0;
  bool handed_over_ = false;  // this call wrote DIR/next.plan
};

}  // namespace excite::host
