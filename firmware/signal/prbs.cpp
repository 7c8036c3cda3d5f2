// SPDX-License-Identifier: MIT
#include "firmware/signal/prbs.hpp"

namespace excite::signal {

PrbsGenerator::PrbsGenerator(const PrbsSource& source, std::uint64_t t0)
    : seq_(source.register_length),
      amplitude_(source.amplitude),
      hold_(source.hold_samples == 0 ? 1U : source.hold_samples) {
  const std::uint64_t period = seq_.period();
  if (period == 0) {  // invalid register length: a zero signal (validate() refuses it)
    amplitude_ = 0.0;
    return;
  }
  const std::uint64_t skip = (std::uint64_t{source.shift} + t0 / hold_) % period;
  seq_.advance(skip);
  level_ = seq_.next() ? amplitude_ : -amplitude_;
  held_ = static_cast<std::uint32_t>(t0 % hold_);
}

}  // namespace excite::signal
