// SPDX-License-Identifier: MIT
#include "firmware/signal/generate.hpp"

#include <algorithm>
#include <array>

#include "firmware/signal/multisine.hpp"
#include "firmware/signal/prbs.hpp"
#include "firmware/signal/steps.hpp"
#include "firmware/signal/validate.hpp"

namespace excite::signal {
namespace {

using U64 = unsigned long long;

// The rows [lo, hi) of the block (absolute sample numbers) that source i covers.
struct Span {
  std::uint32_t lo = 0;
  std::uint32_t hi = 0;
};

Span overlap(const Source& source, std::uint32_t first, std::uint32_t count) {
  const std::uint64_t lo = std::max<std::uint64_t>(source.start, first);
  const std::uint64_t hi = std::min<std::uint64_t>(std::uint64_t{source.start} + source.length,
                                                   std::uint64_t{first} + count);
  if (lo >= hi) return {};
  return {static_cast<std::uint32_t>(lo), static_cast<std::uint32_t>(hi)};
}

// Adds weight[c] · s(k) to every row k of [rows.lo, rows.hi), drawing s from `next`.
template <typename NextValue>
void accumulate(TableView block, std::uint32_t first, Span rows,
                const std::array<double, kMaxChannels>& weight, NextValue&& next) {
  const std::uint32_t channels = block.channels;
  for (std::uint32_t k = rows.lo; k < rows.hi; ++k) {
    const double s = next();
    double* row = block.row(k - first);
    for (std::uint32_t c = 0; c < channels; ++c) row[c] += weight[c] * s;
  }
}

// Scratch for multisines: [unit circle, 2P | one period, P]. The unit circle is rebuilt
// only when the period changes from one source to the next.
class MultisineScratch {
 public:
  explicit MultisineScratch(std::span<double> scratch) : scratch_(scratch) {}

  std::span<const double> period_of(const Recipe& recipe, const MultisineSource& ms) {
    const std::size_t p = ms.period;
    const auto unit_circle = scratch_.subspan(0, 2 * p);
    const auto period = scratch_.subspan(2 * p, p);
    if (tabulated_period_ != p) {
      fill_unit_circle(unit_circle);
      tabulated_period_ = p;
    }
    synthesize_period(std::span<const Line>(recipe.lines).subspan(ms.first_line, ms.line_count),
                      unit_circle, period);
    return period;
  }

 private:
  std::span<double> scratch_;
  std::size_t tabulated_period_ = 0;
};

}  // namespace

std::size_t scratch_size(const Recipe& recipe) {
  std::size_t longest = 0;
  const std::uint32_t count = std::min(recipe.source_count, kMaxSources);
  for (std::uint32_t i = 0; i < count; ++i) {
    if (recipe.sources[i].kind == SourceKind::multisine) {
      longest = std::max<std::size_t>(longest, recipe.sources[i].multisine.period);
    }
  }
  return 3 * longest;
}

Status generate(const Recipe& recipe, TableView table, std::span<double> scratch) {
  if (Status s = validate(recipe); !s) return s;
  if (table.samples != recipe.samples) {
    return Status::error(StatusCode::invalid_field,
                         "table.samples = %u, expected the recipe's samples = %u", table.samples,
                         recipe.samples);
  }
  return generate_block(recipe, 0, table, scratch);
}

Status generate_block(const Recipe& recipe, std::uint32_t first_sample, TableView block,
                      std::span<double> scratch) {
  if (Status s = validate(recipe); !s) return s;
  if (block.channels != recipe.channels) {
    return Status::error(StatusCode::invalid_field,
                         "table.channels = %u, expected the recipe's channels = %u", block.channels,
                         recipe.channels);
  }
  const U64 end = U64{first_sample} + block.samples;
  if (end > recipe.samples) {
    return Status::error(StatusCode::invalid_field,
                         "block samples [%u, %llu), expected inside [0, samples = %u)",
                         first_sample, end, recipe.samples);
  }
  if (block.data == nullptr && block.size() > 0) {
    return Status::error(StatusCode::invalid_field,
                         "table.data = null, expected storage for %llu "
                         "values",
                         U64{block.size()});
  }
  const std::size_t needed = scratch_size(recipe);
  if (scratch.size() < needed) {
    return Status::error(StatusCode::capacity_exceeded,
                         "scratch of %llu doubles, expected ≥ scratch_size(recipe) = %llu",
                         U64{scratch.size()}, U64{needed});
  }

  std::fill(block.data, block.data + block.size(), 0.0);
  MultisineScratch multisine_scratch(scratch);
  for (std::uint32_t i = 0; i < recipe.source_count; ++i) {
    const Source& source = recipe.sources[i];
    const Span rows = overlap(source, first_sample, block.samples);
    if (rows.lo == rows.hi) continue;
    std::array<double, kMaxChannels> weight{};
    for (std::uint32_t c = 0; c < recipe.channels; ++c) weight[c] = recipe.mix[c][i];
    const std::uint64_t t0 = rows.lo - source.start;  // source time of the first row

    switch (source.kind) {
      case SourceKind::steps: {
        StepGenerator steps(source.steps, t0);
        accumulate(block, first_sample, rows, weight, [&] { return steps.next(); });
        break;
      }
      case SourceKind::prbs: {
        PrbsGenerator prbs(source.prbs, t0);
        accumulate(block, first_sample, rows, weight, [&] { return prbs.next(); });
        break;
      }
      case SourceKind::multisine: {
        const std::span<const double> period =
            multisine_scratch.period_of(recipe, source.multisine);
        std::size_t t = static_cast<std::size_t>(t0 % period.size());  // < size(): 32-bit safe
        accumulate(block, first_sample, rows, weight, [&] {
          const double s = period[t];
          if (++t == period.size()) t = 0;
          return s;
        });
        break;
      }
      case SourceKind::none:
        break;  // refused by validate()
    }
  }
  return {};
}

}  // namespace excite::signal
