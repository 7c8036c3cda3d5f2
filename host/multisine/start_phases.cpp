// SPDX-License-Identifier: MIT
#include "host/multisine/start_phases.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "host/multisine/phases.hpp"

namespace excite::host::multisine {

MultisineSet with_start_phases(const MultisineSet& set, StartPhases law, std::size_t position) {
  MultisineSet out = set;
  if (law == StartPhases::given) return out;
  if (law == StartPhases::random) {
    const std::uint64_t seed = position;
    std::uint32_t count = 0;
    for (const auto& lines : out.channels) count += static_cast<std::uint32_t>(lines.size());
    for (const auto& source : out.shared) count += static_cast<std::uint32_t>(source.lines.size());
    const std::vector<double> phases = random_phases(count, seed);
    std::size_t k = 0;
    for (auto& lines : out.channels)
      for (Line& line : lines) line.phase = phases[k++];
    for (auto& source : out.shared)
      for (Line& line : source.lines) line.phase = phases[k++];
    return out;
  }
  if (law == StartPhases::newman) {
    const auto newman = [](std::vector<Line>& lines) {
      const auto N = static_cast<double>(lines.size());
      for (std::size_t k = 0; k < lines.size(); ++k)
        lines[k].phase = std::numbers::pi * static_cast<double>(k * k) / N;
    };
    for (auto& lines : out.channels) newman(lines);
    for (auto& source : out.shared) newman(source.lines);
    return out;
  }
  if (law == StartPhases::grid_schroeder) {
    std::uint32_t top = 1;
    for (const auto& lines : out.channels)
      for (const Line& line : lines) top = std::max(top, line.index);
    for (const auto& source : out.shared)
      for (const Line& line : source.lines) top = std::max(top, line.index);
    const auto by_index = [top](std::vector<Line>& lines) {
      for (Line& line : lines) {
        const double i = line.index;
        line.phase = -std::numbers::pi * i * (i - 1.0) / top;
      }
    };
    for (auto& lines : out.channels) by_index(lines);
    for (auto& source : out.shared) by_index(source.lines);
    return out;
  }
  // channel_schroeder: per channel, 4.4.5 over every line it carries, in index order.
  struct Carried {
    std::uint32_t index;
    double amplitude;
    int source;  // -1: the channel's own line k; else the shared source
    std::size_t line;
  };
  const std::size_t n = out.channels.size();
  // The channel each shared source dominates: its largest |direction| entry.
  std::vector<std::size_t> dominant(out.shared.size(), 0);
  for (std::size_t r = 0; r < out.shared.size(); ++r) {
    for (std::size_t c = 1; c < n; ++c) {
      if (std::abs(out.shared[r].direction[c]) > std::abs(out.shared[r].direction[dominant[r]]))
        dominant[r] = c;
    }
  }
  for (std::size_t c = 0; c < n; ++c) {
    std::vector<Carried> lines;
    for (std::size_t k = 0; k < set.channels[c].size(); ++k)
      lines.push_back({set.channels[c][k].index, set.channels[c][k].amplitude, -1, k});
    for (std::size_t r = 0; r < set.shared.size(); ++r) {
      const double d = set.shared[r].direction[c];
      if (d == 0.0) continue;
      for (std::size_t k = 0; k < set.shared[r].lines.size(); ++k) {
        lines.push_back({set.shared[r].lines[k].index,
                         std::abs(d) * set.shared[r].lines[k].amplitude, static_cast<int>(r), k});
      }
    }
    std::sort(lines.begin(), lines.end(),
              [](const Carried& a, const Carried& b) { return a.index < b.index; });
    std::vector<double> amplitudes;
    for (const Carried& line : lines) amplitudes.push_back(line.amplitude);
    const std::vector<double> phases = schroeder_phases(amplitudes);
    for (std::size_t k = 0; k < lines.size(); ++k) {
      const Carried& line = lines[k];
      if (line.source < 0) {
        out.channels[c][line.line].phase = phases[k];
      } else if (dominant[static_cast<std::size_t>(line.source)] == c) {
        const double d = set.shared[static_cast<std::size_t>(line.source)].direction[c];
        out.shared[static_cast<std::size_t>(line.source)].lines[line.line].phase =
            phases[k] - (d < 0.0 ? std::numbers::pi : 0.0);
      }
    }
  }
  return out;
}

}  // namespace excite::host::multisine
