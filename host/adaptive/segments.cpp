// SPDX-License-Identifier: MIT
#include "host/adaptive/segments.hpp"

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "host/design/prbs_shift.hpp"

namespace excite::host {
namespace {

std::string source_field(std::uint32_t i, const char* field) {
  return "sources[" + std::to_string(i) + "]." + field;
}

}  // namespace

plan::Plan cut_segment(const plan::Plan& design, std::uint64_t first_row, std::uint32_t rows) {
  if (rows == 0) throw std::invalid_argument("segment rows = 0, expected at least 1");
  plan::Plan segment = design;
  segment.recipe.samples = rows;
  for (std::uint32_t i = 0; i < design.recipe.source_count; ++i) {
    const signal::Source& s = design.recipe.sources[i];
    if (s.kind != signal::SourceKind::prbs || s.start != 0 || s.length != design.recipe.samples) {
      throw std::invalid_argument(
          source_field(i, "kind") + " = " + std::to_string(static_cast<int>(s.kind)) +
          " from row " + std::to_string(s.start) + " for " + std::to_string(s.length) +
          " rows, expected a PRBS (2) over the whole table from row 0 (an adaptive test cuts "
          "its segments from such designs)");
    }
    if (first_row % s.prbs.hold_samples != 0) {
      throw std::invalid_argument("segment first row = " + std::to_string(first_row) +
                                  ", expected a multiple of " + source_field(i, "prbs.hold") +
                                  " = " + std::to_string(s.prbs.hold_samples));
    }
    signal::Source& cut = segment.recipe.sources[i];
    cut.length = rows;
    advance_prbs(cut.prbs, first_row / s.prbs.hold_samples);
  }
  return segment;
}

void weight_sources(plan::Plan& plan, const Eigen::VectorXd& weights) {
  if (weights.size() != static_cast<Eigen::Index>(plan.recipe.source_count)) {
    throw std::invalid_argument("direction weights: " + std::to_string(weights.size()) +
                                " values, expected " + std::to_string(plan.recipe.source_count) +
                                " (one per source)");
  }
  for (Eigen::Index i = 0; i < weights.size(); ++i) {
    if (!(std::isfinite(weights(i)) && weights(i) >= 0.0)) {
      throw std::invalid_argument("direction weight " + std::to_string(i + 1) + " = " +
                                  std::to_string(weights(i)) + ", expected a finite value >= 0");
    }
    for (std::uint32_t c = 0; c < plan.recipe.channels; ++c)
      plan.recipe.mix[c][static_cast<std::size_t>(i)] *= weights(i);
  }
}

void scale_mix(plan::Plan& plan, double scale) {
  if (!(std::isfinite(scale) && scale >= 0.0)) {
    throw std::invalid_argument("segment scale = " + std::to_string(scale) +
                                ", expected a finite value >= 0");
  }
  for (auto& row : plan.recipe.mix) {
    for (double& m : row) m *= scale;
  }
}

void set_provenance(plan::Plan& plan, const std::string& text) {
  plan::set_text(plan.meta.provenance, text.substr(0, plan::kProvenanceCapacity - 1));
}

SegmentSources segment_sources(const PriorKnowledge& prior) {
  return {design_preset(prior, find_preset("prbsUnc"), 0)};
}

Design directional_design(const PriorKnowledge& prior, const Eigen::MatrixXd& identified_gain) {
  PriorKnowledge now = prior;
  now.gain = identified_gain;
  return design_preset(now, find_preset("prbsSimDir"), 0);
}

std::uint32_t whole_bit_rows(const plan::Plan& design, double minutes) {
  std::uint64_t hold = 1;
  for (std::uint32_t i = 0; i < design.recipe.source_count; ++i)
    hold = std::lcm(hold, std::uint64_t{design.recipe.sources[i].prbs.hold_samples});
  const double rows = std::ceil(minutes / design.meta.sample_time_min - 1e-9);
  const auto bits =
      static_cast<std::uint64_t>(std::max(1.0, std::ceil(rows / static_cast<double>(hold) - 1e-9)));
  return static_cast<std::uint32_t>(bits * hold);
}

}  // namespace excite::host
