// SPDX-License-Identifier: MIT
#pragma once

#include <chrono>

namespace excite::hal {

// Time on the gateway: a monotonic count of nanoseconds from an arbitrary epoch.
using Nanoseconds = std::chrono::nanoseconds;

// The clock is part of the HAL so the simulator can own time (STYLE.md practice 2):
// PosixClock (hal/posix) reads CLOCK_MONOTONIC and sleeps with an absolute deadline;
// VirtualClock (virtual_clock.hpp) jumps to the deadline at once.
class Clock {
 public:
  virtual ~Clock() = default;
  Clock() = default;
  Clock(const Clock&) = delete;
  Clock& operator=(const Clock&) = delete;

  // Monotonic time now; never decreases.
  [[nodiscard]] virtual Nanoseconds now() const noexcept = 0;

  // Returns at or after the absolute deadline (immediately if it has passed).
  // Absolute deadlines keep a periodic loop free of drift.
  virtual void sleep_until(Nanoseconds deadline) noexcept = 0;
};

}  // namespace excite::hal
