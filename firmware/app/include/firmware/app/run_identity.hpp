// SPDX-License-Identifier: MIT
#pragma once
// The gateway run's identity (issue 39 §3): a random id drawn at start, so that what the
// host tool writes and reads belongs to this run and no other.
//  - the run log's producer line names it: `excite-gateway 0.1.0 (run 5f0c2a91d3e47b68)`;
//  - with --segment-inbox the gateway writes DIR/gateway.run (the run, its pid, its log) for
//    the host tool, and removes it at exit: a tool finds the run it talks to there, reads
//    only a run log naming that run, and sees the gateway gone when the pid is;
//  - a segment names its run in its provenance (`run 5f0c2a91d3e47b68: excite test segment
//    2 …`): a segment of another run is refused, and only a segment of this run may be
//    pre-approved (segments.preapproved_from).
// Start-up and the inbox thread only (they allocate).

#include <optional>
#include <string>
#include <string_view>

namespace excite::app {

/// 16 lowercase hexadecimal digits from the kernel's random source (getrandom).
std::string new_run_id();

/// "run " + id: how a text names a run.
std::string run_tag(std::string_view id);

/// The run a text names ("run " then 16 hexadecimal digits), or nullopt.
std::optional<std::string> run_named_in(std::string_view text);

/// DIR/gateway.run for the host tool: `run ID`, `pid PID`, `log PATH`, one per line, written
/// whole (a temporary name renamed); removed by the destructor while it still names this run.
class RunMarker {
 public:
  RunMarker() = default;
  RunMarker(const RunMarker&) = delete;
  RunMarker& operator=(const RunMarker&) = delete;
  ~RunMarker();

  /// "" when written; else why not ("FIELD = VALUE, expected …").
  std::string write(const std::string& dir, const std::string& id, const std::string& log_path);

 private:
  std::string path_;
  std::string id_;
};

/// The marker's file name in the inbox.
inline constexpr const char* kRunMarkerName = "gateway.run";

}  // namespace excite::app
