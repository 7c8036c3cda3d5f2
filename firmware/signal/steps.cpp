// SPDX-License-Identifier: MIT
#include "firmware/signal/steps.hpp"

namespace excite::signal {

StepGenerator::StepGenerator(const StepSource& source, std::uint64_t t0)
    : source_(&source), segment_(0), remaining_(0) {
  const std::uint32_t count = source.segment_count;
  while (segment_ < count && t0 >= source.segments[segment_].length) {
    t0 -= source.segments[segment_].length;
    ++segment_;
  }
  if (segment_ < count) remaining_ = source.segments[segment_].length - t0;
}

double StepGenerator::next() {
  const std::uint32_t count = source_->segment_count;
  if (segment_ >= count) return 0.0;
  const double value = source_->segments[segment_].level;
  if (--remaining_ == 0) {
    do {
      ++segment_;
    } while (segment_ < count && source_->segments[segment_].length == 0);
    if (segment_ < count) remaining_ = source_->segments[segment_].length;
  }
  return value;
}

}  // namespace excite::signal
