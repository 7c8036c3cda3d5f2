// SPDX-License-Identifier: MIT
#include "host/multisine/allocation.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>

#include "base/config/document.hpp"
#include "host/multisine/phases.hpp"

namespace excite::host::multisine {
namespace {}  // namespace
namespace {

void check_layout(const ZipperedLayout& layout, const char* what) {
  const std::string where(what);
  if (layout.channels == 0) throw std::invalid_argument(where + ": channels = 0, expected >= 1");
  if (layout.lines == 0) {
    throw std::invalid_argument(where + ": lines (n_s): too few lines, expected >= 1 per channel");
  }
  if (!(layout.amplitude > 0.0) || !std::isfinite(layout.amplitude)) {
    throw std::invalid_argument(where + ": amplitude = " + config::format_number(layout.amplitude) +
                                ", expected a finite value > 0");
  }
}

// Lines s(δ + k) + slot, k = 0 … count − 1, flat amplitude, Schroeder phases.
std::vector<Line> slot_lines(std::uint32_t spacing, std::uint32_t first_block, std::uint32_t slot,
                             std::uint32_t count, double amplitude) {
  std::vector<Line> lines(count);
  for (std::uint32_t k = 0; k < count; ++k) {
    lines[k].index = spacing * (first_block + k) + slot;
    lines[k].amplitude = amplitude;
  }
  apply_schroeder(lines);
  return lines;
}

std::vector<std::uint32_t> snow_slots(std::uint32_t spacing, const ZipperedLayout& layout,
                                      std::uint32_t slot) {
  std::vector<std::uint32_t> slots;
  for (std::uint32_t k = 0; k < layout.delta; ++k) slots.push_back(spacing * k + slot);
  for (std::uint32_t k = 0; k < layout.high_snow; ++k) {
    slots.push_back(spacing * (layout.delta + layout.lines + k) + slot);
  }
  return slots;
}

void check_nyquist(std::uint64_t top_index, std::uint32_t period, const char* what) {
  if (2 * top_index >= period) {
    throw std::invalid_argument(std::string(what) + ": band beyond Nyquist: top line " +
                                std::to_string(top_index) + " needs period > " +
                                std::to_string(2 * top_index) + " samples, got " +
                                std::to_string(period));
  }
}

}  // namespace

MultisineSet standard_set(std::uint32_t channels, std::uint32_t period, std::uint32_t first_index,
                          std::uint32_t line_count, double amplitude) {
  ZipperedLayout layout{channels, 0, line_count, 0, amplitude};
  check_layout(layout, "standard_set");
  if (first_index == 0) throw std::invalid_argument("standard_set: first_index = 0, expected >= 1");
  check_nyquist(std::uint64_t{first_index} + line_count - 1, period, "standard_set");
  MultisineSet set;
  set.period = period;
  set.channels.assign(channels, slot_lines(1, 0, first_index, line_count, amplitude));
  set.snow.assign(channels, {});
  validate_set(set);
  return set;
}

MultisineSet zippered_set(std::uint32_t period, const ZipperedLayout& layout) {
  check_layout(layout, "zippered_set");
  const std::uint32_t n = layout.channels;
  check_nyquist(std::uint64_t{n} * (layout.delta + layout.lines + layout.high_snow), period,
                "zippered_set");
  MultisineSet set;
  set.period = period;
  for (std::uint32_t j = 1; j <= n; ++j) {
    set.channels.push_back(slot_lines(n, layout.delta, j, layout.lines, layout.amplitude));
    set.snow.push_back(snow_slots(n, layout, j));
  }
  validate_set(set);
  return set;
}

std::vector<Eigen::VectorXd> weak_input_directions(const Eigen::MatrixXd& gain,
                                                   double xi_threshold) {
  if (gain.rows() == 0 || gain.rows() != gain.cols()) {
    throw std::invalid_argument("weak_input_directions: gain, expected a square n×n G(0), got " +
                                std::to_string(gain.rows()) + "×" + std::to_string(gain.cols()));
  }
  if (!gain.allFinite()) throw std::invalid_argument("weak_input_directions: gain: not finite");
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(gain, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const Eigen::Index n = gain.cols();
  if (!(sigma(n - 1) > 0.0)) {
    throw std::invalid_argument("weak_input_directions: gain: singular (σ_n = 0)");
  }
  std::vector<Eigen::VectorXd> directions;
  for (Eigen::Index i = n - 1; i >= 0; --i) {
    const bool weakest = i == n - 1;
    if (!weakest && !(xi_threshold > 0.0 && sigma(0) / sigma(i) >= xi_threshold)) continue;
    Eigen::VectorXd v = svd.matrixV().col(i).normalized();
    Eigen::Index largest = 0;
    v.cwiseAbs().maxCoeff(&largest);
    if (v(largest) < 0.0) v = -v;
    directions.push_back(v);
  }
  return directions;
}

MultisineSet modified_zippered_set(std::uint32_t period, const ZipperedLayout& layout,
                                   const Eigen::MatrixXd& gain,
                                   const ModifiedZipperedOptions& options) {
  check_layout(layout, "modified_zippered_set");
  if (gain.rows() != layout.channels || gain.cols() != layout.channels) {
    throw std::invalid_argument("modified_zippered_set: gain: " + std::to_string(gain.rows()) +
                                "×" + std::to_string(gain.cols()) + " for " +
                                std::to_string(layout.channels) + " channels (count mismatch)");
  }
  if (!(options.shared_amplitude > 0.0) || !std::isfinite(options.shared_amplitude)) {
    throw std::invalid_argument("modified_zippered_set: shared_amplitude = " +
                                std::to_string(options.shared_amplitude) + ", expected > 0");
  }
  const auto directions = weak_input_directions(gain, options.xi_threshold);
  const std::uint32_t n = layout.channels;
  const auto q = static_cast<std::uint32_t>(directions.size());
  const std::uint32_t spacing = n + q;
  check_nyquist(std::uint64_t{spacing} * (layout.delta + layout.lines + layout.high_snow), period,
                "modified_zippered_set");
  MultisineSet set;
  set.period = period;
  for (std::uint32_t j = 1; j <= n; ++j) {
    set.channels.push_back(slot_lines(spacing, layout.delta, j, layout.lines, layout.amplitude));
    set.snow.push_back(snow_slots(spacing, layout, j));
  }
  for (std::uint32_t r = 1; r <= q; ++r) {
    SharedSource source;
    source.lines = slot_lines(spacing, layout.delta, n + r, layout.lines, options.shared_amplitude);
    const Eigen::VectorXd& v = directions[r - 1];
    source.direction.assign(v.data(), v.data() + v.size());
    set.shared.push_back(std::move(source));
  }
  validate_set(set);
  return set;
}

}  // namespace excite::host::multisine
