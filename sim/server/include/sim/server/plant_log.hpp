// SPDX-License-Identifier: MIT
#pragma once
// excite-plant's run log, one path for every transport (Modbus TCP/RTU and CAN): the
// run-log CSV of firmware/runlog, one row per plant sample, each row written whole by
// runlog::RowFile (write(2) calls of its own, no stdio buffer). A full disk or a file-size
// limit never stops the plant (issue 19): a failed or short row write (ENOSPC, EFBIG with
// SIGXFSZ ignored by main, EIO) cuts the file back to its last whole row and stops logging;
// failure() says why, printed once on stderr at once; serving goes on (the caller keeps
// serving and reports it again at the stop; excite-plant then exits 3).

#include <cstdint>
#include <cstdio>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "firmware/runlog/row_file.hpp"
#include "firmware/runlog/writer.hpp"

namespace excite::sim::server {

/// What the log's header says (from ServeOptions and the plant process).
struct PlantLogSpec {
  std::string path;               // empty: no log
  std::string plant_description;  // the `plant:` line
  double sample_time_min = 0.0;   // T
  runlog::TimeScales time_scales;
  std::vector<std::string> input_names;
  std::vector<std::string> output_names;
  std::vector<std::string> input_units;  // empty entries (or none): "-"
  std::vector<std::string> output_units;
};

class PlantLog {
 public:
  /// Creates (truncates) spec.path and writes the header; nothing when the path is empty.
  /// Throws std::runtime_error naming the file and why ("--log F: cannot write the header:
  /// No space left on device (ENOSPC)"); then no file is left behind.
  explicit PlantLog(PlantLogSpec spec);
  ~PlantLog();
  PlantLog(const PlantLog&) = delete;
  PlantLog& operator=(const PlantLog&) = delete;

  /// Appends sample k (t = k·T; du, u per input, dy per output; flags 0, state unknown: the
  /// plant cannot see the gateway's engine state). No-op without a log or once logging has
  /// stopped. A failed write stops logging (failure() says why). Throws std::runtime_error
  /// only for a row that cannot be formatted (a non-finite number: a programming error).
  void write(std::uint64_t k, std::span<const double> du, std::span<const double> u,
             std::span<const double> dy);

  /// Why logging stopped ("--log plant.csv: cannot write sample 412: No space left on device
  /// (ENOSPC); logging stopped, the log is whole up to its last full row (412 samples);
  /// serving goes on"); "" while every sample is logged (or there is no log).
  const std::string& failure() const { return failure_; }

 private:
  PlantLogSpec spec_;
  std::FILE* file_ = nullptr;
  std::vector<runlog::Channel> inputs_;  // views of spec_'s strings
  std::vector<runlog::Channel> outputs_;
  std::vector<char> buffer_;
  std::string producer_;
  std::optional<runlog::Header> header_;
  std::optional<runlog::RowFile> rows_;
  std::string failure_;
};

}  // namespace excite::sim::server
