// SPDX-License-Identifier: MIT
#include "host/multisine/multisine_set.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "host/multisine/synthesis.hpp"

namespace excite::host::multisine {

void validate_set(const MultisineSet& set) {
  if (set.channels.empty())
    throw std::invalid_argument("multisine set: channels = 0 (none), expected >= 1");
  const std::size_t n = set.channels.size();
  if (!set.snow.empty() && set.snow.size() != n) {
    throw std::invalid_argument("multisine set: snow: " + std::to_string(set.snow.size()) +
                                " lists for " + std::to_string(n) + " channels (count mismatch)");
  }
  for (std::size_t s = 0; s < set.shared.size(); ++s) {
    const auto& source = set.shared[s];
    const std::string name = "multisine set: shared[" + std::to_string(s) + "]";
    validate_lines(source.lines, set.period, name);
    if (source.direction.size() != n) {
      throw std::invalid_argument(name + ".direction: " + std::to_string(source.direction.size()) +
                                  " entries for " + std::to_string(n) +
                                  " channels (count mismatch)");
    }
    double norm2 = 0.0;
    for (double d : source.direction) norm2 += d * d;
    if (std::abs(std::sqrt(norm2) - 1.0) > 1e-9) {
      throw std::invalid_argument(name + ".direction: length " + std::to_string(std::sqrt(norm2)) +
                                  ", expected a unit vector");
    }
  }
  for (std::size_t c = 0; c < n; ++c) {
    const std::string name = "multisine set: channels[" + std::to_string(c) + "]";
    std::vector<std::uint32_t> used;
    if (!set.channels[c].empty()) validate_lines(set.channels[c], set.period, name);
    for (const Line& line : set.channels[c]) used.push_back(line.index);
    for (const auto& source : set.shared) {
      if (source.direction[c] != 0.0) {
        for (const Line& line : source.lines) used.push_back(line.index);
      }
    }
    if (!set.snow.empty()) {
      for (std::uint32_t index : set.snow[c]) {
        if (index == 0 || 2ULL * index >= set.period) {
          throw std::invalid_argument(name + ": snow line " + std::to_string(index) +
                                      ": band beyond Nyquist, expected 0 < index < period/2 = " +
                                      std::to_string(set.period / 2.0));
        }
        used.push_back(index);
      }
    }
    if (used.empty()) throw std::invalid_argument(name + ": too few lines, expected at least 1");
    std::sort(used.begin(), used.end());
    const auto twice = std::adjacent_find(used.begin(), used.end());
    if (twice != used.end()) {
      throw std::invalid_argument(name + ": line index " + std::to_string(*twice) +
                                  " is used twice (own, shared or snow)");
    }
  }
  if (recipe_line_count(set) > excite::signal::kMaxLines) {
    throw std::invalid_argument("multisine set: " + std::to_string(recipe_line_count(set)) +
                                " lines exceed the recipe capacity kMaxLines = " +
                                std::to_string(excite::signal::kMaxLines));
  }
}

std::vector<Line> channel_spectrum(const MultisineSet& set, std::size_t channel) {
  std::vector<Line> lines = set.channels.at(channel);
  for (const auto& source : set.shared) {
    const double d = source.direction.at(channel);
    if (d == 0.0) continue;
    for (Line line : source.lines) {
      line.amplitude *= std::abs(d);
      if (d < 0.0)
        line.phase = std::remainder(line.phase + std::numbers::pi, 2.0 * std::numbers::pi);
      lines.push_back(line);
    }
  }
  std::sort(lines.begin(), lines.end(),
            [](const Line& a, const Line& b) { return a.index < b.index; });
  return lines;
}

std::size_t recipe_line_count(const MultisineSet& set) {
  std::size_t count = 0;
  for (const auto& lines : set.channels) count += lines.size();
  for (const auto& source : set.shared) count += source.lines.size();
  return count;
}

}  // namespace excite::host::multisine
