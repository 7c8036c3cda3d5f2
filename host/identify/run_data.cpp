// SPDX-License-Identifier: MIT
#include "host/identify/run_data.hpp"

#include <stdexcept>
#include <string>

namespace excite::host {

RunData run_data(const runlog::RunLog& log) {
  // Identification assumes one plant run sampled every T: a gap (skipped ticks) or a plant
  // restart (discontinuity) inside the data would be fitted as if it were dynamics.
  for (std::size_t r = 0; r < log.flags.size(); ++r) {
    const std::uint32_t broken = log.flags[r] & (runlog::kSkipped | runlog::kDiscontinuity);
    if (broken == 0U) continue;
    throw std::invalid_argument(
        "row " + std::to_string(r + 1) + " (k = " + std::to_string(log.k[r]) + ") is flagged " +
        ((broken & runlog::kSkipped) != 0U ? "skipped (ticks missing before it)"
                                           : "discontinuity (the plant restarted)") +
        "; identification needs equally spaced samples of one run: use the rows before or "
        "after it");
  }
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
