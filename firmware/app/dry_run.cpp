// SPDX-License-Identifier: MIT
#include "firmware/app/dry_run.hpp"

#include <algorithm>
#include <chrono>

#include "firmware/app/bus_factory.hpp"

namespace excite::app {

void print_dry_run(std::FILE* out, const Gateway& gw, const DistortionVerdict& distortion,
                   bool allow_distortion) {
  const GatewayConfig& config = gw.config();
  const plan::Plan& plan = gw.plan();
  const signal::ConstTableView table = gw.table();
  const engine::EngineConfig& ec = gw.engine_config();
  std::fprintf(out, "dry run: every check passed; nothing was opened or written.\n");
  std::fprintf(out,
               "plan: %s (format v%u), %u channels x %u samples, T = %g min; tick period %g s\n",
               plan::text_of(plan.meta.design_name).data(), unsigned{plan.meta.format_version},
               table.channels, table.samples, gw.sample_time().count(),
               std::chrono::duration<double>(gw.period()).count());
  std::fprintf(out, "device: %s%s\n", describe_peer(config).c_str(),
               config.simulator ? " (a simulated plant)" : "");
  const hal::TransportConfig* bus = config.transport.get();
  std::fprintf(out, "would write every tick, setpoint = baseline (read back at arm) + du:\n");
  for (std::size_t c = 0; c < config.setpoints.size(); ++c) {
    const auto& s = config.setpoints[c];
    double lo = 0.0;
    double hi = 0.0;
    for (std::uint32_t k = 0; k < table.samples; ++k) {
      lo = std::min(lo, table.at(k, static_cast<std::uint32_t>(c)));
      hi = std::max(hi, table.at(k, static_cast<std::uint32_t>(c)));
    }
    std::fprintf(out, "  %-12s %s", s.name.c_str(),
                 bus ? bus->channel_columns(hal::ChannelKind::setpoint, c).c_str() : "");
    std::fprintf(
        out,
        " du in [%g, %g] %s, limits [%g, %g], max move %g/tick, baseline from %s (plan channel "
        "\"%s\")\n",
        lo, hi, s.unit.c_str(), s.min, s.max, s.max_move, s.readback.c_str(),
        plan::text_of(plan.meta.channels[c].name).data());
  }
  if (const std::string heartbeat = bus ? bus->heartbeat_columns() : ""; !heartbeat.empty()) {
    std::fprintf(out, "  heartbeat    %s counter, +1 per tick\n", heartbeat.c_str());
  }
  std::fprintf(out, "would read every tick:\n");
  for (std::size_t j = 0; j < config.values.size(); ++j) {
    const auto& v = config.values[j];
    static const char* roles[] = {"output", "readback", "heartbeat_echo", "command"};
    std::fprintf(out, "  %-12s %s %s", v.name.c_str(),
                 bus ? bus->channel_columns(hal::ChannelKind::value, j).c_str() : "",
                 roles[static_cast<int>(v.role)]);
    if (v.test_low)
      std::fprintf(out, ", test limits [%g, %g] hysteresis %g", *v.test_low, *v.test_high,
                   v.hysteresis);
    std::fprintf(out, "\n");
  }
  std::fprintf(out,
               "ramp %u ticks, resume dwell %u ticks, suspend timeout %u ticks, comm loss after %u "
               "failed exchanges (%s)\n",
               ec.ramp_ticks, ec.resume_dwell_ticks, ec.suspend_timeout_ticks, ec.comm_fail_limit,
               ec.comm_loss == engine::CommLossAction::hold ? "hold" : "ramp to baseline");
  std::fprintf(
      out,
      "verified writes: readback_lag_ticks = %u (1: a tick's reading reflects that tick's "
      "write), more than %u mismatching ticks in a row -> fault; the baseline is written and "
      "read back at arm\n",
      ec.readback_lag_ticks, ec.readback_mismatch_limit);
  const std::uint32_t rows = std::min<std::uint32_t>(table.samples, 5);
  std::fprintf(out, "first %u rows of du:\n", rows);
  for (std::uint32_t k = 0; k < rows; ++k) {
    std::fprintf(out, "  k=%u", k);
    for (std::uint32_t c = 0; c < table.channels; ++c) std::fprintf(out, " %g", table.at(k, c));
    std::fprintf(out, "\n");
  }
  std::fprintf(out,
               "distortion (rows the engine would clamp or rate-limit, per setpoint; at most "
               "%g of the rows allowed%s):\n%s",
               config.max_distortion, allow_distortion ? ", overridden by --allow-distortion" : "",
               distortion.report.c_str());
}

}  // namespace excite::app
