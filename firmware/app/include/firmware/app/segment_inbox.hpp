// SPDX-License-Identifier: MIT
#pragma once
// The segment inbox (README "Plan segments"): a thread beside the tick that watches
// DIR/next.plan (written by the host tool atomically: a temporary file renamed), decodes and
// checks the next plan segment against the running plan, generates its table into the free
// one of two table buffers allocated at start-up, and hands it to the tick
// (segment_handoff.hpp). Not real time: it reads files and allocates; the tick only sees
// atomics and a table view.
//
// A segment taken:   next.plan → segment-N.plan (N = its id, 1, 2, …), stderr
//                    `segment N staged: …; waiting for approval (…)` or `…; pre-approved (…)`
// A segment refused: next.plan → next.plan.refused (or -2, -3, …: never over another),
//                    stderr `segment refused: FIELD = VALUE, expected …; the running
//                    segment M continues (the file is now …; drop a segment atomically: …)`
//                    — not retried. A link, FIFO, folder, another user's file, a file
//                    larger than the largest plan: refused by name, never read through.
// A segment present when the gateway starts (an earlier run's): set_aside_waiting().
// While a staged segment waits (unapproved, or before its boundary), next.plan waits too.

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <span>
#include <string>

#include "firmware/app/gateway_config.hpp"
#include "firmware/app/segment_handoff.hpp"
#include "firmware/app/small_thread.hpp"
#include "firmware/engine/config.hpp"
#include "firmware/plan/plan.hpp"

namespace excite::app {

struct SegmentInboxSetup {
  std::string dir;                                    // where next.plan appears
  const GatewayConfig* config = nullptr;              // [segments], max_distortion, setpoints
  engine::EngineConfig engine_config{};               // limits, max_move (the running one's)
  const plan::Plan* running = nullptr;                // the plan started with (channels, T)
  std::array<double, engine::kMaxInputs> baseline{};  // the armed engine's setpoint baselines
  std::array<std::span<double>, 2> buffers{};         // table storage: segment N uses N % 2
  bool allow_distortion = false;                      // --allow-distortion
  std::FILE* events = nullptr;                        // stderr: staged, refused
  std::string run_id;  // this gateway run's (run_identity.hpp): a segment naming another run
                       // is refused, and only one naming this run may be pre-approved;
                       // "": no run rules (the in-process tests)
};

class SegmentInbox {
 public:
  explicit SegmentInbox(SegmentInboxSetup setup);
  ~SegmentInbox();
  SegmentInbox(const SegmentInbox&) = delete;
  SegmentInbox& operator=(const SegmentInbox&) = delete;

  /// The thread: one poll_once() every `interval_ms` until stop().
  void start(int interval_ms = 50);
  void stop();

  /// One look at DIR/next.plan: true when a segment was staged or refused.
  bool poll_once();

  /// At start-up, before arm: a DIR/next.plan already there was decided before this run, and
  /// is moved aside as refused (named on `events`) unless `take` (--take-waiting-segment).
  /// "" when nothing is left in the way; else the message of a file that could not be moved.
  static std::string set_aside_waiting(const std::string& dir, bool take, std::FILE* events);

  [[nodiscard]] SegmentHandoff& handoff() noexcept { return handoff_; }
  [[nodiscard]] std::uint32_t staged() const noexcept { return staged_.load(); }
  [[nodiscard]] std::uint32_t refused() const noexcept { return refused_.load(); }

 private:
  // "" when `bytes` is a segment the gateway may take; else why not (FIELD = VALUE, expected …).
  std::string check(std::span<const std::uint8_t> bytes, std::uint32_t id, plan::Plan& next,
                    signal::TableView& table);
  void say(const std::string& line);
  void refuse(const std::string& path, const std::string& why, std::uint32_t running);

  SegmentInboxSetup setup_;
  SegmentHandoff handoff_;
  std::atomic<std::uint32_t> staged_{0};
  std::atomic<std::uint32_t> refused_{0};
  std::atomic<bool> stopping_{false};
  SmallThread thread_;
  bool started_ = false;
};

}  // namespace excite::app
