// SPDX-License-Identifier: MIT
#pragma once

#include <cstdint>

#include "excite/hal/clock.hpp"

namespace excite::hal {

// Paces a cyclic loop on a fixed grid: deadline k = start + k * period, slept to with an
// absolute deadline, so the loop does not drift however long each tick's work takes.
// When a tick's work runs past one or more deadlines, those ticks are skipped and
// counted as overruns, and the loop resumes on the next grid point in the future:
// never a burst of back-to-back ticks to catch up.
class PeriodicSchedule {
 public:
  // period must be positive.
  PeriodicSchedule(Clock& clock, Nanoseconds period) noexcept
      : clock_(clock), period_(period), next_(clock.now() + period) {}

  // Sleeps until the next deadline on the grid and returns it (the tick's nominal time).
  Nanoseconds wait_next() noexcept {
    const Nanoseconds now = clock_.now();
    if (now > next_) {
      // Missed deadlines: the number of whole periods elapsed since next_.
      const auto missed = static_cast<std::uint64_t>((now - next_) / period_) + 1U;
      overruns_ += missed;
      next_ += period_ * static_cast<std::int64_t>(missed);
    }
    clock_.sleep_until(next_);
    const Nanoseconds tick = next_;
    next_ += period_;
    ++ticks_;
    return tick;
  }

  [[nodiscard]] std::uint64_t overruns() const noexcept { return overruns_; }  // ticks skipped
  [[nodiscard]] std::uint64_t ticks() const noexcept { return ticks_; }        // ticks run
  [[nodiscard]] Nanoseconds period() const noexcept { return period_; }
  [[nodiscard]] Nanoseconds next_deadline() const noexcept { return next_; }

 private:
  Clock& clock_;
  Nanoseconds period_;
  Nanoseconds next_;
  std::uint64_t overruns_ = 0;
  std::uint64_t ticks_ = 0;
};

}  // namespace excite::hal
