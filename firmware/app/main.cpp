// SPDX-License-Identifier: MIT
// excite-gateway: streams a plan's tables to the field (README.md: command line,
// configuration file, lifecycle, exit codes).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/bus_factory.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/distortion_check.hpp"
#include "firmware/app/dry_run.hpp"
#include "firmware/app/exit_codes.hpp"
#include "firmware/app/gateway.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/app/inbox_files.hpp"
#include "firmware/app/log_drain.hpp"
#include "firmware/app/proc_status.hpp"
#include "firmware/app/realtime.hpp"
#include "firmware/app/run_identity.hpp"
#include "firmware/app/run_log_file.hpp"
#include "firmware/app/run_summary.hpp"
#include "firmware/app/small_thread.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/plan/plan.hpp"
#include "firmware/runlog/format.hpp"
#include "firmware/signal/generate.hpp"
#include "hal/posix/posix_clock.hpp"

namespace {

using excite::app::ExitCode;
namespace engine = excite::engine;

excite::app::CommandMailbox g_commands;
std::atomic<bool> g_hard_stop{false};
std::atomic<int> g_terminations{0};

// Async-signal-safe: only atomics.
extern "C" void on_signal(int signo) {
  switch (signo) {
    case SIGTERM:
    case SIGINT:
      if (g_terminations.fetch_add(1) == 0) {
        g_commands.post(engine::Command::abort);  // ramp out, flush, exit
      } else {
        g_hard_stop.store(true);  // a second one: stop now (the log is still flushed)
      }
      break;
    case SIGUSR1:
      g_commands.post(engine::Command::start);
      break;
    case SIGUSR2:
      g_commands.post(engine::Command::suspend);
      break;
    case SIGHUP:
      g_commands.post(engine::Command::resume);
      break;
    default:
      break;
  }
}

void install_signals() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  for (int signo : {SIGTERM, SIGINT, SIGUSR1, SIGUSR2, SIGHUP}) sigaction(signo, &action, nullptr);
}

// A file-size limit (ulimit -f) must not kill the gateway mid-run: with SIGXFSZ ignored a
// write beyond it fails with EFBIG, which the log thread handles as a fault (ramp out).
// Ignored first thing, before any file is written.
void ignore_file_size_signal() {
  std::signal(SIGXFSZ, SIG_IGN);
}

// Operator commands typed on stdin, one per line: start, suspend, resume, abort, approve.
void read_stdin_commands() {
  static excite::app::SmallThread reader;
  reader.start([] {
    std::string line;
    while (std::getline(std::cin, line)) {
      line.erase(std::remove_if(line.begin(), line.end(), ::isspace), line.end());
      if (line == "start") {
        g_commands.post(engine::Command::start);
      } else if (line == "suspend") {
        g_commands.post(engine::Command::suspend);
      } else if (line == "resume") {
        g_commands.post(engine::Command::resume);
      } else if (line == "abort") {
        g_commands.post(engine::Command::abort);
      } else if (line == "approve") {
        g_commands.post(engine::Command::approve);
      } else if (!line.empty()) {
        std::fprintf(
            stderr,
            "excite-gateway: unknown command \"%s\" (start, suspend, resume, abort, approve)\n",
            line.c_str());
      }
    }
  });
  reader.detach();
}

int fail(ExitCode code, const std::string& message) {
  if (!message.empty()) std::fprintf(stderr, "excite-gateway: %s\n", message.c_str());
  return static_cast<int>(code);
}

int fail(const excite::app::StageError& e) {
  return fail(e.code, e.message);
}

struct Options {
  std::string config_path;
  std::string plan_path;
  std::string log_path;
  std::string clock_mode = "realtime";
  std::string segment_inbox;  // --segment-inbox DIR: "" = no plan segments
  bool dry_run = false;
  bool auto_start = false;
  bool allow_distortion = false;
  bool take_waiting_segment = false;  // --take-waiting-segment: a next.plan there at start
  [[nodiscard]] bool lockstep() const { return clock_mode == "lockstep"; }
};

// The command line (README "Command line"); an exit code when there is nothing to run
// (--help, --version: 0; a bad command line: usage).
std::optional<int> parse_command_line(int argc, char** argv, Options& opt) {
  CLI::App cli{"excite-gateway: streams an excite plan to the field bus (firmware/app/README.md)"};
  cli.add_option("--config", opt.config_path, "gateway configuration (TOML)")->required();
  cli.add_option("--plan", opt.plan_path, "plan file written by `excite design`")->required();
  cli.add_option("--log", opt.log_path, "run log to write (CSV, firmware/runlog format)");
  cli.add_option("--clock", opt.clock_mode,
                 "realtime: one tick per period; lockstep: tick as soon as the previous exchange "
                 "returned (a simulated plant owns the clock; [device] simulator = true)")
      ->check(CLI::IsMember({"realtime", "lockstep"}))
      ->capture_default_str();
  cli.add_option("--segment-inbox", opt.segment_inbox,
                 "a folder where the next plan segment appears as next.plan (written to a "
                 "temporary file and renamed); taken at a boundary once approved")
      ->check(CLI::ExistingDirectory);
  cli.add_flag("--take-waiting-segment", opt.take_waiting_segment,
               "take a next.plan already in the segment inbox at start (by default it was "
               "decided before this run and is refused)");
  cli.add_flag("--dry-run", opt.dry_run, "validate everything and print what would be written");
  cli.add_flag("--start", opt.auto_start, "start streaming right after arming (no start command)");
  cli.add_flag("--allow-distortion", opt.allow_distortion,
               "stream a plan even when more than gateway.max_distortion of a channel's rows "
               "would be clamped or rate-limited (reported either way)");
  cli.set_version_flag("--version", "excite-gateway " + std::string(excite::runlog::kVersion));
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : static_cast<int>(ExitCode::usage);
  }
  if (!opt.dry_run && opt.log_path.empty()) {
    return fail(ExitCode::usage, "--log is required (except with --dry-run)");
  }
  if (opt.take_waiting_segment && opt.segment_inbox.empty()) {
    return fail(ExitCode::usage, "--take-waiting-segment = set, expected with --segment-inbox");
  }
  return std::nullopt;
}

// The segment inbox at start (README "Plan segments", inbox rules): a folder of this user's
// that nobody else can write, and no segment decided before this run left in it.
excite::app::StageResult check_segment_inbox(const Options& opt) {
  if (opt.segment_inbox.empty() || opt.dry_run) return std::nullopt;
  if (std::string e = excite::app::check_inbox_folder(opt.segment_inbox); !e.empty()) {
    return excite::app::StageError{ExitCode::usage, e};
  }
  if (std::string e = excite::app::SegmentInbox::set_aside_waiting(
          opt.segment_inbox, opt.take_waiting_segment, stderr);
      !e.empty()) {
    return excite::app::StageError{ExitCode::usage, e};
  }
  return std::nullopt;
}

// 1. Lock-step only against a simulated plant.
excite::app::StageResult check_clock(const excite::app::GatewayConfig& config, const Options& opt) {
  if (!opt.lockstep() || config.simulator) return std::nullopt;
  return excite::app::StageError{
      ExitCode::usage, "--clock lockstep refused: " + opt.config_path +
                           ": device.simulator = false, expected true (lockstep lets the peer "
                           "set the pace, which only a simulated plant may do; a real plant "
                           "runs in real time)"};
}

// 2.–3. Plan → table in fixed storage, checked against the plan's limits → engine; the
// bus's timing against the tick period.
excite::app::StageResult load_plan(excite::app::Gateway& gw, const Options& opt) {
  std::ifstream plan_in(opt.plan_path, std::ios::binary);
  if (!plan_in) {
    return excite::app::StageError{ExitCode::bad_plan,
                                   opt.plan_path + ": cannot open the plan file"};
  }
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(plan_in)),
                                        std::istreambuf_iterator<char>());
  if (auto e = gw.load_plan(bytes, opt.plan_path)) return e;
  const double period_s = std::chrono::duration<double>(gw.period()).count();
  if (std::string e = excite::app::check_bus_timing(gw.config(), period_s); !e.empty()) {
    return excite::app::StageError{ExitCode::bad_config, opt.config_path + ": " + e};
  }
  return std::nullopt;
}

// The clock the gateway ticks on: the POSIX clock, or in lock-step `lockstep` (its
// sleep_until returns at once: the peer paces). Whatever the tick clock, the real clock
// times what is real: the quiet interval before arm (one owner: another master writing is
// refused). In lock-step also: the baseline is not written at arm (README: verified writes,
// lock-step); a retry after a failed exchange waits 250 ms on the real clock, never the
// period — the plant's time stands still while exchanges fail (README: paced retries); the
// suspension and confirmation timeouts end on the real clock at the latest; a segment
// awaited at the table's end (segments.await_s) is awaited without ticking, timed on the
// real clock.
excite::hal::Clock& tick_clock(excite::app::Gateway& gw, const Options& opt,
                               excite::hal::PosixClock& real, excite::hal::VirtualClock& lockstep) {
  gw.set_verify_at_arm(!opt.lockstep());
  gw.observe_quiet_on(&real, gw.quiet_interval(opt.lockstep()));
  gw.read_before_write(!opt.lockstep());  // one owner: a write between two ticks is seen
  if (!opt.lockstep()) return real;
  gw.await_segments_on(&real);  // [segments] await_s: stop ticking, timed on the real clock
  gw.pace_retries(&real, excite::app::kRetryPacing);
  gw.time_on_real_clock(&real);
  return lockstep;
}

// Armed: the segment inbox (with this run's marker for the host tool), real time, signals,
// operator input, and the start-up's last words on stderr.
void go_live(excite::app::Gateway& gw, const Options& opt, const std::string& run_id,
             excite::app::RunMarker& marker) {
  if (!opt.segment_inbox.empty()) {
    gw.start_segments(opt.segment_inbox, opt.allow_distortion, stderr, run_id);
    std::fprintf(stderr,
                 "excite-gateway: watching %s/next.plan for the next plan segment (this run's "
                 "segments name \"%s\")\n",
                 opt.segment_inbox.c_str(), excite::app::run_tag(run_id).c_str());
    if (std::string e = marker.write(opt.segment_inbox, run_id, opt.log_path); !e.empty()) {
      std::fprintf(stderr, "excite-gateway: warning: %s\n", e.c_str());
    }
  }
  const excite::app::RealtimeResult rt = excite::app::make_realtime(gw.config().realtime_priority);
  for (const auto& w : rt.warnings)
    std::fprintf(stderr, "excite-gateway: warning: %s\n", w.c_str());
  install_signals();
  read_stdin_commands();
  const std::string pace =
      opt.lockstep()
          ? "lockstep: each tick as soon as the previous exchange returned; a retry after a "
            "failure waits 250 ms and the timeouts end on the real clock"
          : "period " + std::to_string(std::chrono::duration<double>(gw.period()).count()) + " s";
  std::fprintf(
      stderr, "excite-gateway: armed (%u setpoints, %u values, %u rows, T = %g min, %s)%s\n",
      gw.engine_config().inputs, gw.engine_config().values, gw.table().samples,
      gw.sample_time().count(), pace.c_str(),
      opt.auto_start ? "; starting" : "; waiting for start (SIGUSR1, stdin, command register)");
  std::fprintf(stderr, "excite-gateway: memory after start-up: %s\n",
               excite::app::memory_status().c_str());
  if (opt.auto_start) g_commands.post(engine::Command::start);
}

}  // namespace

// Start-up order (README): nothing is written to the field before every check has passed.
// The distortion is judged once, from the plan: rate limiting does not depend on the
// baseline, and arm refuses a baseline + table that would be clamped.
int main(int argc, char** argv) {
  using namespace excite::app;
  ignore_file_size_signal();
  Options opt;
  if (const std::optional<int> rc = parse_command_line(argc, argv, opt)) return *rc;
  if (auto e = check_segment_inbox(opt)) return fail(*e);
  ConfigResult loaded = load_gateway_config(opt.config_path);
  if (!loaded.config) return fail(ExitCode::bad_config, loaded.error);
  if (auto e = check_clock(*loaded.config, opt)) return fail(*e);
  Gateway gw(std::move(*loaded.config));
  if (auto e = load_plan(gw, opt)) return fail(*e);
  const DistortionVerdict distortion =
      check_distortion(gw.config(), gw.engine_config(), gw.table(), {}, opt.allow_distortion);
  if (!distortion.refusal.empty()) return fail(ExitCode::distorted, distortion.refusal);
  if (opt.dry_run) {
    print_dry_run(stdout, gw, distortion, opt.allow_distortion);
    return static_cast<int>(ExitCode::ok);
  }
  // The log file, then the bus (connects; nothing written), then arm: the baseline written
  // once and read back. A failure here removes the log file again.
  RunLogFile log(opt.log_path);
  if (!log.is_open()) return fail(ExitCode::log_error, opt.log_path + ": cannot open for writing");
  excite::hal::PosixClock real_clock;
  excite::hal::VirtualClock lockstep_clock;  // sleep_until returns at once: the peer paces
  const BusResult made = make_field_bus(gw.config(), real_clock, opt.lockstep());
  if (!made.bus) return fail(ExitCode::device, opt.config_path + ": " + made.error);
  if (const std::string e = check_written_values(gw.config(), *made.bus); !e.empty()) {
    return fail(ExitCode::bad_config, opt.config_path + ": " + e);
  }
  if (auto e = gw.arm(*made.bus, tick_clock(gw, opt, real_clock, lockstep_clock))) return fail(*e);
  std::fprintf(stderr, "excite-gateway: distortion (at most %g of the rows%s):\n%s",
               gw.config().max_distortion,
               opt.allow_distortion ? ", overridden by --allow-distortion" : "",
               distortion.report.c_str());
  log.keep();  // the run's record from here on, whatever happens
  gw.set_event_stream(stderr);
  // This run's identity (run_identity.hpp): in the log's producer line, the inbox's marker,
  // and every segment the host tool writes for this run.
  const std::string run_id = new_run_id();
  std::fprintf(stderr, "excite-gateway: %s\n", run_tag(run_id).c_str());
  const std::string producer =
      "excite-gateway " + std::string(excite::runlog::kVersion) + " (" + run_tag(run_id) + ")";
  if (auto e = gw.start_log(log.get(), producer)) {
    return fail(e->code, opt.log_path + ": " + e->message);
  }
  RunMarker marker;  // removed at exit
  go_live(gw, opt, run_id, marker);
  const RunStats stats = gw.run(g_commands, &g_hard_stop);
  gw.stop_segments();
  if (const SegmentInbox* inbox = gw.segments()) {
    std::fprintf(stderr, "excite-gateway: segments: %u staged, %u refused, %u taken\n",
                 inbox->staged(), inbox->refused(), gw.engine().segment());
  }
  const RunSummary summary = finish_run(gw, stats, made, log);
  print_summary(stderr, summary);
  return fail(verdict(summary));
}
