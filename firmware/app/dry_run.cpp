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
  const bool can = config.transport == Transport::can;
  std::fprintf(out, "would write every tick, setpoint = baseline (read back at arm) + du:\n");
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
      std::fprintf(out, "  %-12s CAN 0x%03X byte %u %-7s %-6s scale %g offset %g", s.name.c_str(),
                   g.id, g.byte_offset, g.type.c_str(), g.byte_order.c_str(), g.scale, g.offset);
    } else {
      const auto& r = config.modbus.map.setpoints[c];
      std::fprintf(out, "  %-12s register %5u %-7s %-4s", s.name.c_str(), r.address, r.type.c_str(),
                   r.type == "float32" ? r.word_order.c_str() : "");
    }
    std::fprintf(
        out,
        " du in [%g, %g] %s, limits [%g, %g], max move %g/tick, baseline from %s (plan channel "
        "\"%s\")\n",
        lo, hi, s.unit.c_str(), s.min, s.max, s.max_move, s.readback.c_str(),
        plan::text_of(plan.meta.channels[c].name).data());
  }
  if (!can && config.modbus.map.heartbeat_address) {
    std::fprintf(out, "  heartbeat    register %5u uint16 counter, +1 per tick\n",
                 *config.modbus.map.heartbeat_address);
  }
  if (can && config.can.map.heartbeat) {
    const auto& h = *config.can.map.heartbeat;
    std::fprintf(out, "  heartbeat    CAN 0x%03X byte %u %s counter, +1 per tick\n", h.id,
                 h.byte_offset, h.type.c_str());
  }
  std::fprintf(out, "would read every tick:\n");
  for (std::size_t j = 0; j < config.values.size(); ++j) {
    const auto& v = config.values[j];
    static const char* roles[] = {"output", "readback", "heartbeat_echo", "command"};
    if (can) {
      const auto& g = config.can.map.values[j];
      std::fprintf(out, "  %-12s CAN 0x%03X byte %u %-7s %s", v.name.c_str(), g.id, g.byte_offset,
                   g.type.c_str(), roles[static_cast<int>(v.role)]);
    } else {
      const auto& r = config.modbus.map.values[j];
      std::fprintf(out, "  %-12s register %5u FC%02d %-7s %s", v.name.c_str(), r.address,
                   r.function_code, r.type.c_str(), roles[static_cast<int>(v.role)]);
    }
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
