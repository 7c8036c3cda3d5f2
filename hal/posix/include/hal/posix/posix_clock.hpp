// SPDX-License-Identifier: MIT
#pragma once

#include "excite/hal/clock.hpp"

namespace excite::hal {

// The real clock: now() is CLOCK_MONOTONIC (unaffected by wall-clock changes);
// sleep_until() is clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), restarted after a
// signal, so a periodic loop sleeping to absolute deadlines does not drift.
class PosixClock final : public Clock {
 public:
  [[nodiscard]] Nanoseconds now() const noexcept override;
  void sleep_until(Nanoseconds deadline) noexcept override;
};

}  // namespace excite::hal
