// SPDX-License-Identifier: MIT
#include "firmware/app/closed_loop_log.hpp"

#include <string_view>

namespace excite::app {
namespace {

std::string_view without_prefix(std::string_view name, std::string_view prefix) {
  return name.size() > prefix.size() && name.substr(0, prefix.size()) == prefix
             ? name.substr(prefix.size())
             : name;
}

std::vector<const ValueSpec*> with_role(const GatewayConfig& c, ValueRole role) {
  std::vector<const ValueSpec*> out;
  for (const ValueSpec& v : c.values)
    if (v.role == role) out.push_back(&v);
  return out;
}

}  // namespace

ClosedLoopLogLayout closed_loop_log_layout(const GatewayConfig& config, std::size_t outputs,
                                           std::vector<runlog::Channel>& inputs) {
  const auto status = with_role(config, ValueRole::mv_status);
  const auto applied = with_role(config, ValueRole::applied_mv);
  const auto move = with_role(config, ValueRole::controller_move);
  const std::size_t mvs = status.size();
  inputs.clear();
  for (std::size_t i = 0; i < mvs; ++i) {
    const std::string_view name = i < applied.size() ? without_prefix(applied[i]->name, "ua_")
                                                     : without_prefix(status[i]->name, "st_");
    const std::string_view unit = i < applied.size() ? std::string_view(applied[i]->unit)
                                  : i < move.size()  ? std::string_view(move[i]->unit)
                                                     : std::string_view("-");
    inputs.push_back({name, unit});
  }
  ClosedLoopLogLayout layout;
  const std::string& kind = config.closed_loop->offsets;
  const std::size_t setpoints = config.setpoints.size();
  if (kind == "mv") {
    layout.excitation = runlog::Excitation::mv;
    for (std::size_t c = 0; c < setpoints && c < mvs; ++c) {
      layout.r_channels.push_back(c);
      layout.r_source.push_back(static_cast<std::uint32_t>(c));
    }
  } else if (kind == "setpoint") {
    layout.excitation = runlog::Excitation::setpoint;
    for (std::size_t c = 0; c < setpoints && c < outputs; ++c) {
      layout.r_channels.push_back(c);
      layout.r_source.push_back(static_cast<std::uint32_t>(c));
    }
  } else {  // both: r columns of the outputs (CV offsets, after the MV offsets) first
    layout.excitation = runlog::Excitation::both;
    const std::size_t mv_offsets = setpoints < mvs ? setpoints : mvs;
    for (std::size_t j = 0; mv_offsets + j < setpoints && j < outputs; ++j) {
      layout.r_channels.push_back(j);
      layout.r_source.push_back(static_cast<std::uint32_t>(mv_offsets + j));
    }
    for (std::size_t i = 0; i < mv_offsets; ++i) {
      layout.r_channels.push_back(outputs + i);
      layout.r_source.push_back(static_cast<std::uint32_t>(i));
    }
  }
  layout.mv_baseline = config.closed_loop->mv_baseline;
  layout.mv_baseline.resize(mvs, 0.0);
  return layout;
}

}  // namespace excite::app
