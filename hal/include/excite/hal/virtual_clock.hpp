// SPDX-License-Identifier: MIT
#pragma once

#include <atomic>
#include <cstdint>

#include "excite/hal/clock.hpp"

namespace excite::hal {

// A clock the simulator owns: time stands still until someone sleeps or advances it;
// sleep_until jumps to the deadline at once, so simulated runs are deterministic and
// faster than real time. Safe to read from several threads.
class VirtualClock final : public Clock {
 public:
  explicit VirtualClock(Nanoseconds start = Nanoseconds{0}) noexcept : now_ns_(start.count()) {}

  [[nodiscard]] Nanoseconds now() const noexcept override {
    return Nanoseconds{now_ns_.load(std::memory_order_acquire)};
  }

  // Time jumps to the deadline; a deadline in the past leaves time where it is.
  void sleep_until(Nanoseconds deadline) noexcept override {
    std::int64_t current = now_ns_.load(std::memory_order_acquire);
    while (current < deadline.count() &&
           !now_ns_.compare_exchange_weak(current, deadline.count(), std::memory_order_acq_rel)) {
    }
  }

  // The simulator (or a test) spends time, e.g. the duration of one tick's work.
  void advance(Nanoseconds step) noexcept {
    if (step.count() > 0) {
      now_ns_.fetch_add(step.count(), std::memory_order_acq_rel);
    }
  }

 private:
  std::atomic<std::int64_t> now_ns_;
};

}  // namespace excite::hal
