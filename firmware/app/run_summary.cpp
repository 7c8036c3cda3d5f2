// SPDX-License-Identifier: MIT
#include "firmware/app/run_summary.hpp"

#include <chrono>

#include "firmware/app/proc_status.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/runlog/format.hpp"

namespace excite::app {

namespace {

unsigned long long n(std::uint64_t count) {
  return static_cast<unsigned long long>(count);
}

}  // namespace

RunSummary finish_run(Gateway& gw, const RunStats& stats, const BusResult& made, RunLogFile& log) {
  RunSummary s;
  s.stats = stats;
  s.log_path = log.path();
  s.log_status = gw.finish_log();
  s.log_failure = gw.log_failure();
  s.log_closed = log.close();
  s.memory = memory_status();
  const engine::Engine& eng = gw.engine();
  s.cut_short = !engine::finished(stats.final_state);
  s.rows_logged = gw.rows_logged();
  s.comm_losses = eng.comm_losses();
  s.suspensions = eng.suspensions();
  s.readback_mismatches = eng.readback_mismatches();
  s.ticks_skipped = eng.skipped_ticks();
  s.stale_writes_undone = eng.stale_writes_undone();
  s.closed_loop = gw.config().closed_loop.has_value();
  s.acknowledge_command = eng.config().acknowledge_command;
  s.commands_acknowledged = eng.commands_acknowledged();
  s.controller_mode_losses = eng.controller_mode_losses();
  s.mv_limited = eng.mv_limited_episodes();
  s.rows_clamped = eng.rows_flagged(runlog::kClamped);
  s.rows_rate_limited = eng.rows_flagged(runlog::kRateLimited);
  s.rows_suspended = eng.rows_flagged(runlog::kSuspended);
  s.rows_comm_lost = eng.rows_flagged(runlog::kCommLost);
  s.rows_stale = eng.rows_flagged(runlog::kStale);
  s.rows_skipped = eng.rows_flagged(runlog::kSkipped);
  s.rows_discontinuity = eng.rows_flagged(runlog::kDiscontinuity);
  s.segment_await_s = gw.config().segment_await_s;
  s.rows_awaiting = eng.awaited_ticks();
  s.bus_counts = bus_counts_report(made);
  s.refusal = gw.refusal_report();
  s.readback_fault = gw.readback_fault_report();
  s.foreign_write = gw.foreign_write_report();
  s.range_ends = gw.range_end_report();
  s.confirm_timeout_s = gw.config().confirm_timeout_s;
  return s;
}

void print_summary(std::FILE* out, const RunSummary& s) {
  const RunStats& st = s.stats;
  std::fprintf(out, "excite-gateway: memory after the run: %s\n", s.memory.c_str());
  std::fprintf(out,
               "excite-gateway: %s after %llu ticks (%s); rows logged %llu, ring overruns %llu, "
               "failed exchanges %llu, comm losses %llu, suspensions %llu, readback mismatches "
               "%llu, schedule overruns %llu\n",
               s.cut_short ? "stopped before the baseline was reached (ramp-out cut short)"
                           : engine::to_string(st.final_state),
               n(st.ticks), engine::to_string(st.outcome), n(s.rows_logged), n(st.ring_overruns),
               n(st.failed_exchanges), n(s.comm_losses), n(s.suspensions), n(s.readback_mismatches),
               n(st.schedule_overruns));
  std::fprintf(out,
               "excite-gateway: rows: clamped %llu, rate-limited %llu, suspended %llu, "
               "comm-lost %llu, stale %llu, skipped %llu (ticks skipped %llu), discontinuity "
               "%llu; reads before writing again after a failed exchange %llu; stale writes "
               "undone %llu; retries paced %llu\n",
               n(s.rows_clamped), n(s.rows_rate_limited), n(s.rows_suspended), n(s.rows_comm_lost),
               n(s.rows_stale), n(s.rows_skipped), n(s.ticks_skipped), n(s.rows_discontinuity),
               n(st.reverified), n(s.stale_writes_undone), n(st.paced));
  if (s.segment_await_s > 0.0) {
    const auto seconds = [](hal::Nanoseconds t) {
      return std::chrono::duration<double>(t).count();
    };
    std::fprintf(out,
                 "excite-gateway: awaiting segments (segments.await_s = %g s): rows holding the "
                 "baseline %llu; waits without ticking %llu, %.3f s in all, longest %.3f s\n",
                 s.segment_await_s, n(s.rows_awaiting), n(st.segment_waits),
                 seconds(st.segment_wait), seconds(st.longest_segment_wait));
  }
  if (s.acknowledge_command) {
    std::fprintf(out,
                 "excite-gateway: command register: cleared after %llu readings (the "
                 "acknowledgement); clears that failed %llu\n",
                 n(s.commands_acknowledged), n(st.command_clear_failures));
  }
  if (s.closed_loop) {
    std::fprintf(out,
                 "excite-gateway: closed loop: the controller left its mode %llu times, MVs "
                 "clamped or wound up %llu times (each suspended the test)\n",
                 n(s.controller_mode_losses), n(s.mv_limited));
  }
  if (!s.bus_counts.empty()) std::fprintf(out, "excite-gateway: %s\n", s.bus_counts.c_str());
  if (!s.refusal.empty()) std::fprintf(out, "excite-gateway: fault: %s\n", s.refusal.c_str());
  if (!s.readback_fault.empty()) {
    std::fprintf(out, "excite-gateway: fault: verified write failed: %s\n",
                 s.readback_fault.c_str());
  }
  if (!s.foreign_write.empty()) {
    std::fprintf(out, "excite-gateway: fault: %s\n", s.foreign_write.c_str());
  }
  if (st.final_state == engine::State::safe_unconfirmed) {
    std::fprintf(out,
                 "excite-gateway: safe, unconfirmed: the baseline was written but not read back "
                 "twice, a hold interval apart, within gateway.confirm_timeout_s = %g s (check "
                 "the field)%s\n",
                 s.confirm_timeout_s,
                 s.closed_loop ? ", or the controller was not in its mode (control or test) "
                                 "while the offsets read back zero"
                               : "");
  }
  std::fprintf(out, "excite-gateway: values at the end of their register's range: %s\n",
               s.range_ends.empty() ? "none" : s.range_ends.c_str());
}

StageError verdict(const RunSummary& s) {
  const RunStats& st = s.stats;
  if (s.cut_short) return {ExitCode::hard_stop, ""};
  if (st.final_state == engine::State::safe_unconfirmed) return {ExitCode::unconfirmed, ""};
  if (st.outcome == engine::Outcome::readback_fault) return {ExitCode::fault, ""};
  if (st.outcome == engine::Outcome::foreign_writer) return {ExitCode::fault, ""};
  if (st.outcome == engine::Outcome::device_refused) return {ExitCode::device_refused, ""};
  if (!s.log_failure.empty()) {
    return {ExitCode::log_fault, "fault: " + s.log_path + ": " + s.log_failure +
                                     (st.outcome == engine::Outcome::log_fault
                                          ? "; the excitation was stopped and the baseline "
                                            "confirmed"
                                          : "; the baseline was confirmed")};
  }
  if (!s.log_closed || s.log_status != runlog::WriteStatus::ok) {
    return {ExitCode::log_error, s.log_path + ": writing the run log failed: " +
                                     std::string(runlog::describe(s.log_status))};
  }
  if (st.ring_overruns > 0) {
    return {ExitCode::log_incomplete, "the log ring overran: " + std::to_string(st.ring_overruns) +
                                          " ticks are missing from " + s.log_path};
  }
  if (st.outcome == engine::Outcome::completed) return {ExitCode::ok, ""};
  return {ExitCode::aborted, ""};
}

}  // namespace excite::app
