// SPDX-License-Identifier: MIT
#include "firmware/app/distortion_check.hpp"

#include <cstdio>

#include "firmware/engine/distortion.hpp"

namespace excite::app {

namespace {

std::string format(const char* fmt, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

}  // namespace

DistortionVerdict check_distortion(const GatewayConfig& config,
                                   const engine::EngineConfig& engine_config,
                                   signal::ConstTableView table, std::span<const double> baseline,
                                   bool allow) {
  const engine::Distortion d = engine::predict_distortion(engine_config, table, baseline);
  DistortionVerdict v;
  std::string worst;
  for (std::uint32_t c = 0; c < engine_config.inputs && c < config.setpoints.size(); ++c) {
    const engine::ChannelDistortion& ch = d.channel[c];
    const SetpointSpec& s = config.setpoints[c];
    const double fraction = d.fraction(c);
    const std::string clamped = d.clamping_known
                                    ? format("%u clamped", ch.clamped_rows)
                                    : std::string(
                                          "clamping known at arm (needs the baseline; arm "
                                          "refuses a clamped row)");
    const std::string line = format(
        "%s: %u of %u rows rate-limited, %s (%.4g %% of the rows); largest move %.6g %s at row "
        "%u, max_move %.6g",
        s.name.c_str(), ch.rate_limited_rows, d.rows, clamped.c_str(), 100.0 * fraction,
        ch.largest_move, s.unit.c_str(), ch.largest_move_row, s.max_move);
    v.report += "  " + line + "\n";
    if (fraction > config.max_distortion) worst += (worst.empty() ? "" : "; ") + line;
  }
  if (!worst.empty() && !allow) {
    v.refusal = std::string("the plan would be distorted: ") + worst +
                format(
                    ", expected at most gateway.max_distortion = %g of each channel's rows "
                    "(%s; --allow-distortion streams it anyway)",
                    config.max_distortion, config.source.c_str());
  }
  return v;
}

}  // namespace excite::app
