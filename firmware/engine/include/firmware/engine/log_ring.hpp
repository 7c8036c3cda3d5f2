// SPDX-License-Identifier: MIT
#pragma once
// The run-log ring: the real-time tick pushes one TickRecord per tick, a non-real-time
// thread pops them into the CSV. Single producer, single consumer, lock-free, fixed
// capacity (STYLE.md practice 4: LogRing<N> reserves the storage, LogRingBase is the
// capacity-erased API). The producer never blocks: when the ring is full the record is
// dropped and counted in overruns() — reported, never silent.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware/engine/tick_record.hpp"

namespace excite::engine {

class LogRingBase {
 public:
  LogRingBase(const LogRingBase&) = delete;
  LogRingBase& operator=(const LogRingBase&) = delete;

  /// Producer: copies `record` in; false (and one more overrun) when the ring is full.
  bool push(const TickRecord& record) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    if (head - tail >= slots_.size()) {
      overruns_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    slots_[static_cast<std::size_t>(head % slots_.size())] = record;  // < size(): 32-bit safe
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer: copies the oldest record out; false when the ring is empty.
  bool pop(TickRecord& out) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    if (tail == head) return false;
    out = slots_[static_cast<std::size_t>(tail % slots_.size())];  // < size(): 32-bit safe
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  [[nodiscard]] std::size_t capacity() const noexcept { return slots_.size(); }
  [[nodiscard]] std::uint64_t pushed() const noexcept {
    return head_.load(std::memory_order_acquire);
  }
  [[nodiscard]] std::uint64_t overruns() const noexcept {
    return overruns_.load(std::memory_order_acquire);
  }

 protected:
  explicit LogRingBase(std::span<TickRecord> slots) noexcept : slots_(slots) {}
  ~LogRingBase() = default;

 private:
  std::span<TickRecord> slots_;
  std::atomic<std::uint64_t> head_{0};  // next slot to write (producer)
  std::atomic<std::uint64_t> tail_{0};  // next slot to read (consumer)
  std::atomic<std::uint64_t> overruns_{0};
};

/// A ring over caller-owned storage (sized once at start-up, e.g. from the configuration).
class SpanLogRing final : public LogRingBase {
 public:
  explicit SpanLogRing(std::span<TickRecord> storage) noexcept : LogRingBase(storage) {}
};

/// A ring of N records (N ≥ 1). Large: allocate once at start-up (or make it static).
template <std::size_t N>
class LogRing final : public LogRingBase {
  static_assert(N >= 1, "LogRing<N>: N = 0, expected at least one record");

 public:
  LogRing() noexcept : LogRingBase(std::span<TickRecord>(storage_)) {}

 private:
  TickRecord storage_[N];
};

}  // namespace excite::engine
