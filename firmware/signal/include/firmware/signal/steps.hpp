// SPDX-License-Identifier: MIT
#pragma once
// Step source (4.2.1): segments one after another from the window start, each `level`
// held `length` samples; zero after the last segment.

#include <cstdint>

#include "firmware/signal/recipe.hpp"

namespace excite::signal {

/// Produces s(t0), s(t0 + 1), … of a step source (precondition: validate()d).
class StepGenerator {
 public:
  explicit StepGenerator(const StepSource& source, std::uint64_t t0 = 0);

  double next();

 private:
  const StepSource* source_;
  std::uint32_t segment_;    // current segment; == segment_count after the last
  std::uint64_t remaining_;  // samples left in the current segment
};

}  // namespace excite::signal
