// SPDX-License-Identifier: MIT
#include "host/design/time_constant_bound.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/design/case_studies.hpp"
#include "host/output/text_table.hpp"

namespace excite::host {

std::pair<double, std::string> time_constant_bound(const TimeConstantBoundOptions& o,
                                                   const std::vector<RunTimeScales>& runs) {
  if (o.max_time_constant_min > 0.0) return {o.max_time_constant_min, "--max-time-constant"};
  if (o.max_time_constant_min == 0.0) return {0.0, "the run's length, --max-time-constant 0"};
  const auto beta_of = [&](const RunTimeScales* r) {
    return o.beta > 0.0 ? o.beta : r != nullptr && r->beta > 0.0 ? r->beta : 3.0;
  };
  if (o.tau_high_min > 0.0) {
    const double beta = beta_of(runs.empty() ? nullptr : &runs.front());
    return {beta * o.tau_high_min, "beta " + num(beta) + " x --tau-high"};
  }
  const RunTimeScales* widest = nullptr;
  for (const RunTimeScales& r : runs) {
    if (r.tau_high_min <= 0.0) continue;
    if (widest == nullptr ||
        beta_of(&r) * r.tau_high_min > beta_of(widest) * widest->tau_high_min) {
      widest = &r;
    }
  }
  if (widest != nullptr) {
    const double beta = beta_of(widest);
    return {beta * widest->tau_high_min, "beta x tau_H of the run log " + widest->path +
                                             ", beta = " + num(beta) +
                                             ", tau_H = " + num(widest->tau_high_min) + " min"};
  }
  const std::vector<std::string> known = case_study_plants();
  for (const RunTimeScales& r : runs) {
    if (std::find(known.begin(), known.end(), r.plant) == known.end()) continue;
    const PriorKnowledge prior = case_study(r.plant);
    const double beta = o.beta > 0.0 ? o.beta : prior.beta;
    return {beta * prior.tau_high_min, "beta x tau_H of the " + r.plant + " case study, tau_H = " +
                                           num(prior.tau_high_min) + " min"};
  }
  const std::string path = runs.empty() ? std::string("the run") : runs.front().path;
  throw std::invalid_argument(
      path + ": tau_high_min = (not in the run log's header, and plant \"" +
      (runs.empty() ? std::string() : runs.front().plant) +
      "\" has no case study), expected the design's time scale: give --tau-high MIN (the bound "
      "is beta x tau_H), --max-time-constant MIN, or --max-time-constant 0 to accept the run's "
      "length (an element may then absorb another's misfit with a slow lag and a large gain)");
}

}  // namespace excite::host
