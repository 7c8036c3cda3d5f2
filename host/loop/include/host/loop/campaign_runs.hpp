// SPDX-License-Identifier: MIT
#pragma once
// The campaign's measured runs made in the loop (`excite campaign --loop`): each plan
// streamed by the real excite-gateway to the real excite-plant (stream_in_the_loop), in
// lock-step, with the experiment's noise and seed, so the study reports on what the gateway
// logged. Each experiment keeps its folder RUNS/NN-name: the plan, plant.toml and
// gateway.toml, run.csv (the gateway's log) and plant.csv (the plant's).

#include <filesystem>
#include <functional>
#include <string>

#include "host/campaign/campaign.hpp"
#include "host/loop/stream.hpp"

namespace excite::host {

/// "07-prbsDirCorrSeq": the folder (and model file) name of Table 6.1's experiment.
std::string experiment_folder(int number, const std::string& name);

/// The gateway's run log as the campaign's measured data, laid out by identify's flags rule
/// (host/identify/run_layout.hpp, default FlagRule): rows flagged suspended, comm_lost,
/// clamped, stale or bad_value not scored, a new segment at a discontinuity, skipped ticks
/// and after a comm_lost span, the warm-up after it not scored (issue 23 §4). `name` labels
/// errors.
MeasuredData measured_data(const runlog::RunLog& log, const std::string& name);

/// A MeasuredRun for run_campaign that streams through `programs` for `plant`; `say` (may
/// be empty) gets one line per streamed plan. Throws what stream_in_the_loop throws.
MeasuredRun measured_runs_in_the_loop(const std::string& plant, const std::filesystem::path& runs,
                                      const LoopPrograms& programs,
                                      const std::function<void(const std::string&)>& say);

}  // namespace excite::host
