// SPDX-License-Identifier: MIT
// The plan codec allocates nothing (STYLE.md practice 5): this executable replaces the
// global operator new and delete with counting versions.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "firmware/plan/codec.hpp"
#include "firmware/plan/limits.hpp"
#include "firmware/signal/generate.hpp"
#include "tests/unit/plan/example_plan.hpp"

namespace {
std::atomic<long> g_allocations{0};

void* counted_alloc(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  std::abort();
}
}  // namespace

void* operator new(std::size_t size) {
  return counted_alloc(size);
}
void* operator new[](std::size_t size) {
  return counted_alloc(size);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}

namespace excite::plan {
namespace {

TEST(PlanCodecAllocation, EncodesDecodesAndChecksLimitsWithoutAllocating) {
  // GIVEN a plan, a decoded copy, buffers for the file and the table, prepared beforehand
  const auto plan = testing::example_plan();
  auto decoded = std::make_unique<Plan>();
  std::vector<std::uint8_t> file(max_encoded_size());
  std::vector<double> table(4 * 4080);
  std::vector<double> scratch(signal::scratch_size(plan->recipe));
  // WHEN the plan is encoded, decoded (also a corrupted copy), generated and checked
  const long before = g_allocations.load();
  const EncodeResult encoded = encode(*plan, file);
  const Status decoded_status = decode(std::span(file).first(encoded.size), *decoded);
  const Status generated = signal::generate(decoded->recipe, {table.data(), 4, 4080}, scratch);
  const LimitCheck limits = check_limits(*decoded, {table.data(), 4, 4080});
  file[40] ^= 1U;
  const Status refused = decode(std::span(file).first(encoded.size), *decoded);
  const long during = g_allocations.load() - before;
  // THEN all worked as expected and nothing was allocated
  EXPECT_TRUE(encoded.status) << encoded.status.message();
  EXPECT_TRUE(decoded_status) << decoded_status.message();
  EXPECT_TRUE(generated) << generated.message();
  EXPECT_TRUE(limits.status) << limits.status.message();
  EXPECT_EQ(refused.code(), StatusCode::checksum_mismatch);
  EXPECT_EQ(during, 0);
}

}  // namespace
}  // namespace excite::plan
