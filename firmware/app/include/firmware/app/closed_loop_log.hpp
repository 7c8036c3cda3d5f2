// SPDX-License-Identifier: MIT
#pragma once
// The gateway's run log in closed loop (run-log v4, firmware/runlog/README.md "Version 4";
// README "Closed loop", the run log): which channels the log's inputs are and which offset
// each r column comes from, taken once from the configuration at start-up (allocates).
//
// The log's inputs are the MVs (what the plant got: du_/u_ are the applied MVs read back),
// one per `mv_status` value, named after the i-th `applied_mv` value without a leading
// `ua_` (else the i-th `mv_status` value without a leading `st_`); its outputs are the
// `output` values, as in the open loop. The setpoints the gateway writes are the offsets:
// `[closed_loop] offsets = "mv"`: the i-th setpoint is MV i's offset; "setpoint": the j-th
// is CV j's setpoint offset; "both": first one MV offset per `mv_status` value, then the CV
// setpoint offsets (the order `excite loop-config --controller` writes).

#include <cstddef>
#include <cstdint>
#include <vector>

#include "firmware/app/gateway_config.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::app {

struct ClosedLoopLogLayout {
  runlog::Excitation excitation = runlog::Excitation::setpoint;
  std::vector<std::size_t> r_channels;  // the header's r channels (runlog::ClosedLoopHeader)
  std::vector<std::uint32_t> r_source;  // per r column: the setpoint (offset) it logs
  std::vector<double> mv_baseline;      // per MV: u = mv_baseline + du applied (zeros: none)
};

/// The MVs as the log's input channels (names and units point into `config`, which must
/// outlive them) and the r mapping; `outputs` is the log's output count. An offset beyond
/// the MVs or outputs is left out of r (its readback still verifies it).
ClosedLoopLogLayout closed_loop_log_layout(const GatewayConfig& config, std::size_t outputs,
                                           std::vector<runlog::Channel>& inputs);

}  // namespace excite::app
