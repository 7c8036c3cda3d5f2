// SPDX-License-Identifier: MIT
#pragma once
// A run log (firmware/runlog) as identification data: U from the du_* columns, Y from the
// dy_* columns, T from sample_time_min.

#include <Eigen/Dense>

#include "firmware/runlog/reader.hpp"

namespace excite::host {

struct RunData {
  Eigen::MatrixXd U;  // N × n input deviations
  Eigen::MatrixXd Y;  // N × p output deviations
  double sample_time_min = 0.0;
};

/// Copies the deviation columns of a log that read_run_log() accepted. Throws
/// std::invalid_argument (naming the row) when a row is flagged skipped or discontinuity
/// (format v2): the samples are then not one equally spaced run.
RunData run_data(const runlog::RunLog& log);

}  // namespace excite::host
