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
#include <string>
#include <thread>
#include <vector>

#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/bus_factory.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/distortion_check.hpp"
#include "firmware/app/exit_codes.hpp"
#include "firmware/app/gateway.hpp"
#include "firmware/app/gateway_config.hpp"
#include "firmware/app/log_drain.hpp"
#include "firmware/app/proc_status.hpp"
#include "firmware/app/realtime.hpp"
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

// Operator commands typed on stdin, one per line: start, suspend, resume, abort.
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
      } else if (!line.empty()) {
        std::fprintf(stderr,
                     "excite-gateway: unknown command \"%s\" (start, suspend, resume, abort)\n",
                     line.c_str());
      }
    }
  });
  reader.detach();
}

int fail(ExitCode code, const std::string& message) {
  std::fprintf(stderr, "excite-gateway: %s\n", message.c_str());
  return static_cast<int>(code);
}

void print_dry_run(const excite::app::Gateway& gw) {
  const excite::app::GatewayConfig& config = gw.config();
  const excite::plan::Plan& plan = gw.plan();
  const excite::signal::ConstTableView table = gw.table();
  const engine::EngineConfig& ec = gw.engine_config();
  std::printf("dry run: every check passed; nothing was opened or written.\n");
  std::printf("plan: %s (format v%u), %u channels x %u samples, T = %g min; tick period %g s\n",
              excite::plan::text_of(plan.meta.design_name).data(),
              unsigned{plan.meta.format_version}, table.channels, table.samples,
              gw.sample_time().count(), std::chrono::duration<double>(gw.period()).count());
  std::printf("device: %s%s\n", excite::app::describe_peer(config).c_str(),
              config.simulator ? " (a simulated plant)" : "");
  const bool can = config.transport == excite::app::Transport::can;
  std::printf("would write every tick, setpoint = baseline (read back at arm) + du:\n");
  for (std::size_t c = 0; c < config.setpoints.size(); ++c) {
    const auto& s = config.setpoints[c];
    double lo = 0.0;
    double hi = 0.0;
    for (std::uint32_t k = 0; k < table.samples; ++k) {
      lo = std::min(lo, table.at(k, static_cast<std::uint32_t>(c)));
      hi = std::max(hi, table.at(k, static_cast<std::uint32_t>(c)));
    }
    if (can) {
      const auto& g = config.can.map.setpoints[c];
      std::printf("  %-12s CAN 0x%03X byte %u %-7s %-6s scale %g offset %g", s.name.c_str(), g.id,
                  g.byte_offset, g.type.c_str(), g.byte_order.c_str(), g.scale, g.offset);
    } else {
      const auto& r = config.modbus.map.setpoints[c];
      std::printf("  %-12s register %5u %-7s %-4s", s.name.c_str(), r.address, r.type.c_str(),
                  r.type == "float32" ? r.word_order.c_str() : "");
    }
    std::printf(
        " du in [%g, %g] %s, limits [%g, %g], max move %g/tick, baseline from %s (plan channel "
        "\"%s\")\n",
        lo, hi, s.unit.c_str(), s.min, s.max, s.max_move, s.readback.c_str(),
        excite::plan::text_of(plan.meta.channels[c].name).data());
  }
  if (!can && config.modbus.map.heartbeat_address) {
    std::printf("  heartbeat    register %5u uint16 counter, +1 per tick\n",
                *config.modbus.map.heartbeat_address);
  }
  if (can && config.can.map.heartbeat) {
    const auto& h = *config.can.map.heartbeat;
    std::printf("  heartbeat    CAN 0x%03X byte %u %s counter, +1 per tick\n", h.id, h.byte_offset,
                h.type.c_str());
  }
  std::printf("would read every tick:\n");
  for (std::size_t j = 0; j < config.values.size(); ++j) {
    const auto& v = config.values[j];
    static const char* roles[] = {"output", "readback", "heartbeat_echo", "command"};
    if (can) {
      const auto& g = config.can.map.values[j];
      std::printf("  %-12s CAN 0x%03X byte %u %-7s %s", v.name.c_str(), g.id, g.byte_offset,
                  g.type.c_str(), roles[static_cast<int>(v.role)]);
    } else {
      const auto& r = config.modbus.map.values[j];
      std::printf("  %-12s register %5u FC%02d %-7s %s", v.name.c_str(), r.address, r.function_code,
                  r.type.c_str(), roles[static_cast<int>(v.role)]);
    }
    if (v.test_low)
      std::printf(", test limits [%g, %g] hysteresis %g", *v.test_low, *v.test_high, v.hysteresis);
    std::printf("\n");
  }
  std::printf(
      "ramp %u ticks, resume dwell %u ticks, suspend timeout %u ticks, comm loss after %u "
      "failed exchanges (%s)\n",
      ec.ramp_ticks, ec.resume_dwell_ticks, ec.suspend_timeout_ticks, ec.comm_fail_limit,
      ec.comm_loss == engine::CommLossAction::hold ? "hold" : "ramp to baseline");
  std::printf(
      "verified writes: readback_lag_ticks = %u (1: a tick's reading reflects that tick's "
      "write), more than %u mismatching ticks in a row -> fault; the baseline is written and "
      "read back at arm\n",
      ec.readback_lag_ticks, ec.readback_mismatch_limit);
  const std::uint32_t rows = std::min<std::uint32_t>(table.samples, 5);
  std::printf("first %u rows of du:\n", rows);
  for (std::uint32_t k = 0; k < rows; ++k) {
    std::printf("  k=%u", k);
    for (std::uint32_t c = 0; c < table.channels; ++c) std::printf(" %g", table.at(k, c));
    std::printf("\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  ignore_file_size_signal();
  CLI::App cli{"excite-gateway: streams an excite plan to the field bus (firmware/app/README.md)"};
  std::string config_path;
  std::string plan_path;
  std::string log_path;
  std::string clock_mode = "realtime";
  bool dry_run = false;
  bool auto_start = false;
  cli.add_option("--config", config_path, "gateway configuration (TOML)")->required();
  cli.add_option("--plan", plan_path, "plan file written by `excite design`")->required();
  cli.add_option("--log", log_path, "run log to write (CSV, firmware/runlog format)");
  cli.add_option("--clock", clock_mode,
                 "realtime: one tick per period; lockstep: tick as soon as the previous exchange "
                 "returned (a simulated plant owns the clock; [device] simulator = true)")
      ->check(CLI::IsMember({"realtime", "lockstep"}))
      ->capture_default_str();
  cli.add_flag("--dry-run", dry_run, "validate everything and print what would be written");
  cli.add_flag("--start", auto_start, "start streaming right after arming (no start command)");
  bool allow_distortion = false;
  cli.add_flag("--allow-distortion", allow_distortion,
               "stream a plan even when more than gateway.max_distortion of a channel's rows "
               "would be clamped or rate-limited (reported either way)");
  cli.set_version_flag("--version", "excite-gateway " + std::string(excite::runlog::kVersion));
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? 0 : static_cast<int>(ExitCode::usage);
  }
  if (!dry_run && log_path.empty()) {
    return fail(ExitCode::usage, "--log is required (except with --dry-run)");
  }
  const bool lockstep = clock_mode == "lockstep";

  // 1. Configuration.
  excite::app::ConfigResult loaded = excite::app::load_gateway_config(config_path);
  if (!loaded.config) return fail(ExitCode::bad_config, loaded.error);
  if (lockstep && !loaded.config->simulator) {
    return fail(ExitCode::usage,
                "--clock lockstep refused: " + config_path +
                    ": device.simulator = false, expected true (lockstep lets the peer set the "
                    "pace, which only a simulated plant may do; a real plant runs in real time)");
  }
  excite::app::Gateway gw(std::move(*loaded.config));
  const excite::app::GatewayConfig& config = gw.config();

  // 2.–3. Plan → table in fixed storage, checked against the plan's limits → engine.
  std::ifstream plan_in(plan_path, std::ios::binary);
  if (!plan_in) return fail(ExitCode::bad_plan, plan_path + ": cannot open the plan file");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(plan_in)),
                                        std::istreambuf_iterator<char>());
  if (auto e = gw.load_plan(bytes, plan_path)) return fail(e->code, e->message);
  if (const std::string e =
          excite::app::check_bus_timing(config, std::chrono::duration<double>(gw.period()).count());
      !e.empty()) {
    return fail(ExitCode::bad_config, config_path + ": " + e);
  }
  // Distortion before anything is opened: rate limiting is known from the plan alone.
  const excite::app::DistortionVerdict planned =
      excite::app::check_distortion(config, gw.engine_config(), gw.table(), {}, allow_distortion);
  if (dry_run) {
    if (!planned.refusal.empty()) return fail(ExitCode::distorted, planned.refusal);
    print_dry_run(gw);
    std::printf(
        "distortion (rows the engine would clamp or rate-limit, per setpoint; at most "
        "%g of the rows allowed%s):\n%s",
        config.max_distortion, allow_distortion ? ", overridden by --allow-distortion" : "",
        planned.report.c_str());
    return static_cast<int>(ExitCode::ok);
  }
  if (!planned.refusal.empty()) return fail(ExitCode::distorted, planned.refusal);

  // Log file, then the bus (connects; nothing written), then arm (reads only).
  std::FILE* log = std::fopen(log_path.c_str(), "w");
  if (log == nullptr) return fail(ExitCode::log_error, log_path + ": cannot open for writing");
  excite::hal::PosixClock real_clock;
  excite::hal::VirtualClock lockstep_clock;  // sleep_until returns at once: the peer paces
  excite::hal::Clock& tick_clock =
      lockstep ? static_cast<excite::hal::Clock&>(lockstep_clock) : real_clock;
  excite::app::BusResult made = excite::app::make_field_bus(config, real_clock, lockstep);
  if (!made.bus) {
    std::fclose(log);
    std::remove(log_path.c_str());
    return fail(ExitCode::device, config_path + ": " + made.error);
  }
  gw.set_verify_at_arm(!lockstep);  // README: verified writes, lock-step
  // Lock-step never sleeps out a period: after a failed exchange, retry at most 4 times a
  // second (and never sooner than the period) on the real clock (README: paced retries).
  if (lockstep) {
    gw.pace_retries(&real_clock, std::max<excite::hal::Nanoseconds>(
                                     gw.period(), std::chrono::milliseconds(250)));
  }
  if (auto e = gw.arm(*made.bus, tick_clock)) {
    std::fclose(log);
    std::remove(log_path.c_str());
    return fail(e->code, e->message);
  }

  // Distortion again with the baseline read at arm: clamping is known now. Refused before
  // anything but the baseline was written.
  std::vector<double> baseline(gw.engine_config().inputs);
  for (std::uint32_t c = 0; c < gw.engine_config().inputs; ++c)
    baseline[c] = gw.engine().baseline(c);
  const excite::app::DistortionVerdict armed = excite::app::check_distortion(
      config, gw.engine_config(), gw.table(), baseline, allow_distortion);
  std::fprintf(stderr, "excite-gateway: distortion at arm (at most %g of the rows%s):\n%s",
               config.max_distortion, allow_distortion ? ", overridden by --allow-distortion" : "",
               armed.report.c_str());
  if (!armed.refusal.empty()) {
    std::fclose(log);
    std::remove(log_path.c_str());
    return fail(ExitCode::distorted, armed.refusal);
  }

  // Run log header and thread.
  gw.set_event_stream(stderr);
  if (auto e = gw.start_log(log, "excite-gateway " + std::string(excite::runlog::kVersion))) {
    std::fclose(log);
    return fail(e->code, log_path + ": " + e->message);
  }

  // Real time, signals, operator input; run.
  const excite::app::RealtimeResult rt = excite::app::make_realtime(config.realtime_priority);
  for (const auto& w : rt.warnings)
    std::fprintf(stderr, "excite-gateway: warning: %s\n", w.c_str());
  install_signals();
  read_stdin_commands();
  std::fprintf(
      stderr, "excite-gateway: armed (%u setpoints, %u values, %u rows, T = %g min, %s)%s\n",
      gw.engine_config().inputs, gw.engine_config().values, gw.table().samples,
      gw.sample_time().count(),
      lockstep
          ? "lockstep: each tick as soon as the previous exchange returned"
          : ("period " + std::to_string(std::chrono::duration<double>(gw.period()).count()) + " s")
                .c_str(),
      auto_start ? "; starting" : "; waiting for start (SIGUSR1, stdin, command register)");
  std::fprintf(stderr, "excite-gateway: memory after start-up: %s\n",
               excite::app::memory_status().c_str());
  if (auto_start) g_commands.post(engine::Command::start);
  const excite::app::RunStats stats = gw.run(g_commands, &g_hard_stop);
  const excite::runlog::WriteStatus log_status = gw.finish_log();
  const std::string log_failure = gw.log_failure();
  const bool closed = std::fclose(log) == 0;
  std::fprintf(stderr, "excite-gateway: memory after the run: %s\n",
               excite::app::memory_status().c_str());

  const engine::Engine& eng = gw.engine();
  const bool cut_short = !engine::finished(stats.final_state);
  std::fprintf(
      stderr,
      "excite-gateway: %s after %llu ticks (%s); rows logged %llu, ring overruns %llu, "
      "failed exchanges %llu, comm losses %llu, suspensions %llu, readback mismatches %llu, "
      "schedule overruns %llu\n",
      cut_short ? "stopped before the baseline was reached (ramp-out cut short)"
                : engine::to_string(stats.final_state),
      static_cast<unsigned long long>(stats.ticks), engine::to_string(stats.outcome),
      static_cast<unsigned long long>(gw.rows_logged()),
      static_cast<unsigned long long>(stats.ring_overruns),
      static_cast<unsigned long long>(stats.failed_exchanges),
      static_cast<unsigned long long>(eng.comm_losses()),
      static_cast<unsigned long long>(eng.suspensions()),
      static_cast<unsigned long long>(eng.readback_mismatches()),
      static_cast<unsigned long long>(stats.schedule_overruns));
  // Rows of the run log per condition (README "End-of-run summary"): what the log's flags
  // say, counted by the engine as it set them.
  std::fprintf(stderr,
               "excite-gateway: rows: clamped %llu, rate-limited %llu, suspended %llu, "
               "comm-lost %llu, stale %llu, skipped %llu (ticks skipped %llu), discontinuity "
               "%llu; reads before writing again after a failed exchange %llu; stale writes "
               "undone %llu; retries paced %llu\n",
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kClamped)),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kRateLimited)),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kSuspended)),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kCommLost)),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kStale)),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kSkipped)),
               static_cast<unsigned long long>(eng.skipped_ticks()),
               static_cast<unsigned long long>(eng.rows_flagged(excite::runlog::kDiscontinuity)),
               static_cast<unsigned long long>(stats.reverified),
               static_cast<unsigned long long>(eng.stale_writes_undone()),
               static_cast<unsigned long long>(stats.paced));
  std::fprintf(stderr, "excite-gateway: exception replies by code: %s\n",
               gw.exception_report(*made.bus).c_str());
  if (const std::string counts = excite::app::bus_counts_report(made); !counts.empty()) {
    std::fprintf(stderr, "excite-gateway: %s\n", counts.c_str());
  }
  const std::string refused = gw.refusal_report();
  if (!refused.empty()) std::fprintf(stderr, "excite-gateway: fault: %s\n", refused.c_str());
  if (eng.readback_fault().valid) {
    std::fprintf(stderr, "excite-gateway: fault: verified write failed: %s\n",
                 gw.readback_fault_report().c_str());
  }
  if (stats.final_state == engine::State::safe_unconfirmed) {
    std::fprintf(stderr,
                 "excite-gateway: safe, unconfirmed: the baseline was written but not read back "
                 "twice, a hold interval apart, within gateway.confirm_timeout_s = %g s (check "
                 "the field)\n",
                 config.confirm_timeout_s);
  }
  const std::string at_end = gw.range_end_report();
  std::fprintf(stderr, "excite-gateway: values at the end of their register's range: %s\n",
               at_end.empty() ? "none" : at_end.c_str());
  // The field's state first (exit_codes.hpp), then the log's, then how the run ended.
  if (cut_short) return static_cast<int>(ExitCode::hard_stop);
  if (stats.final_state == engine::State::safe_unconfirmed) {
    return static_cast<int>(ExitCode::unconfirmed);
  }
  if (stats.outcome == engine::Outcome::readback_fault) return static_cast<int>(ExitCode::fault);
  if (stats.outcome == engine::Outcome::device_refused) {
    return static_cast<int>(ExitCode::device_refused);
  }
  if (!log_failure.empty()) {
    return fail(ExitCode::log_fault,
                std::string("fault: ") + log_path + ": " + log_failure +
                    (stats.outcome == engine::Outcome::log_fault
                         ? "; the excitation was stopped and the baseline confirmed"
                         : "; the baseline was confirmed"));
  }
  if (!closed || log_status != excite::runlog::WriteStatus::ok) {
    return fail(ExitCode::log_error, log_path + ": writing the run log failed: " +
                                         std::string(excite::runlog::describe(log_status)));
  }
  if (stats.ring_overruns > 0) {
    return fail(ExitCode::log_incomplete,
                "the log ring overran: " + std::to_string(stats.ring_overruns) +
                    " ticks are missing from " + log_path);
  }
  if (stats.outcome == engine::Outcome::completed) return static_cast<int>(ExitCode::ok);
  return static_cast<int>(ExitCode::aborted);
}
