// SPDX-License-Identifier: MIT
#pragma once
// excite-plant's controller log (`--controller-log FILE`, README "Closed loop"): what the
// controller in the plant's loop did, one row per plant sample and one per watchdog trip,
// CSV:
//
//   event,k,t_min,mode,o_<u>…,uc_<u>…,du_<u>…,st_<u>…,ysp_<y>…
//
// event `sample` (sample k: the offsets o applied, the controller's move uc, the applied
// MV du — deviations —, each MV's status 0..4, the CV setpoints in force) or `watchdog`
// (the heartbeat stood still: every offset returned to zero, k the next sample, the
// values as they stand after it); mode off, control, test or suspended. The plant's run
// log (--log) stays the open-loop v3 format, its du/u what the plant got. A failed write
// stops this log (failure() says why) and never the plant.

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "sim/server/closed_loop.hpp"

namespace excite::sim::server {

class ControllerLog {
 public:
  /// Creates (truncates) `path` and writes the header line; nothing when `path` is empty.
  /// Throws std::runtime_error naming the file when it cannot be created.
  ControllerLog(std::string path, const std::vector<std::string>& input_names,
                const std::vector<std::string>& output_names, double sample_time_min);
  ~ControllerLog();
  ControllerLog(const ControllerLog&) = delete;
  ControllerLog& operator=(const ControllerLog&) = delete;

  void write(const char* event, std::uint64_t k, const ClosedLoop& loop);
  const std::string& failure() const { return failure_; }

 private:
  std::string path_;
  std::FILE* file_ = nullptr;
  double sample_time_min_ = 1.0;
  std::string failure_;
};

}  // namespace excite::sim::server
