// SPDX-License-Identifier: MIT
#include "host/identify/run_data.hpp"

namespace excite::host {

RunData run_data(const runlog::RunLog& log) {
  const auto N = static_cast<Eigen::Index>(log.rows());
  RunData d;
  d.sample_time_min = log.sample_time_min;
  d.U.resize(N, static_cast<Eigen::Index>(log.du.size()));
  d.Y.resize(N, static_cast<Eigen::Index>(log.dy.size()));
  for (std::size_t i = 0; i < log.du.size(); ++i) {
    d.U.col(static_cast<Eigen::Index>(i)) = Eigen::Map<const Eigen::VectorXd>(log.du[i].data(), N);
  }
  for (std::size_t j = 0; j < log.dy.size(); ++j) {
    d.Y.col(static_cast<Eigen::Index>(j)) = Eigen::Map<const Eigen::VectorXd>(log.dy[j].data(), N);
  }
  return d;
}

}  // namespace excite::host
