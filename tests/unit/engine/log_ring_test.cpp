// SPDX-License-Identifier: MIT
// The run-log ring: FIFO order, full ring drops and counts, a second thread drains all.
#include "firmware/engine/log_ring.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <thread>

namespace excite::engine {
namespace {

TickRecord numbered(std::uint64_t k) {
  TickRecord r;
  r.tick = k;
  r.u[0] = static_cast<double>(k);
  return r;
}

TEST(LogRingTest, PopsInPushOrder) {
  auto ring = std::make_unique<LogRing<4>>();
  for (std::uint64_t k = 0; k < 3; ++k) EXPECT_TRUE(ring->push(numbered(k)));
  TickRecord r;
  for (std::uint64_t k = 0; k < 3; ++k) {
    ASSERT_TRUE(ring->pop(r));
    EXPECT_EQ(r.tick, k);
    EXPECT_EQ(r.u[0], static_cast<double>(k));
  }
  EXPECT_FALSE(ring->pop(r));
}

TEST(LogRingTest, AFullRingDropsTheNewRecordAndCountsIt) {
  auto ring = std::make_unique<LogRing<4>>();
  for (std::uint64_t k = 0; k < 6; ++k) ring->push(numbered(k));
  EXPECT_EQ(ring->overruns(), 2U);
  EXPECT_EQ(ring->pushed(), 4U);
  TickRecord r;
  ASSERT_TRUE(ring->pop(r));
  EXPECT_EQ(r.tick, 0U);  // the oldest records are kept
}

TEST(LogRingTest, ConsumerThreadReceivesEveryRecordPushed) {
  auto ring = std::make_unique<LogRing<64>>();
  constexpr std::uint64_t kCount = 200000;
  std::uint64_t received = 0;
  std::uint64_t expected_next = 0;
  bool in_order = true;
  std::atomic<bool> done{false};
  std::thread consumer([&] {
    TickRecord r;
    while (true) {
      if (ring->pop(r)) {
        in_order = in_order && r.tick == expected_next;
        expected_next = r.tick + 1;
        ++received;
      } else if (done.load()) {
        if (!ring->pop(r)) break;
        in_order = in_order && r.tick == expected_next;
        expected_next = r.tick + 1;
        ++received;
      }
    }
  });
  std::uint64_t pushed = 0;
  for (std::uint64_t k = 0; k < kCount; ++k) {
    while (!ring->push(numbered(pushed))) {
    }
    ++pushed;
  }
  done = true;
  consumer.join();
  EXPECT_EQ(received, kCount);
  EXPECT_TRUE(in_order);
  EXPECT_EQ(ring->overruns() + ring->pushed(), ring->overruns() + kCount);
}

}  // namespace
}  // namespace excite::engine
