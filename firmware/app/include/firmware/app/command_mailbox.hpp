// SPDX-License-Identifier: MIT
#pragma once
// Operator commands from outside the tick (signal handlers, the stdin reader) to the tick:
// one lock-free atomic slot, async-signal-safe to post; the last command posted wins.

#include <atomic>
#include <cstdint>

#include "firmware/engine/state.hpp"

namespace excite::app {

class CommandMailbox {
 public:
  void post(engine::Command c) noexcept {
    slot_.store(static_cast<std::uint8_t>(c), std::memory_order_release);
  }
  engine::Command take() noexcept {
    return static_cast<engine::Command>(slot_.exchange(0, std::memory_order_acq_rel));
  }

 private:
  std::atomic<std::uint8_t> slot_{0};
  static_assert(std::atomic<std::uint8_t>::is_always_lock_free);
};

}  // namespace excite::app
