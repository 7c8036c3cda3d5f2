// SPDX-License-Identifier: MIT
// Proves that generation allocates nothing (STYLE.md practice 5): this executable
// replaces the global operator new and delete with counting versions.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <vector>

#include "firmware/signal/generate.hpp"
#include "tests/unit/signal/example_recipes.hpp"

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
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return counted_alloc(size);
}
void* operator new[](std::size_t size, const std::nothrow_t&) noexcept {
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

namespace excite::signal {
namespace {

TEST(GenerateAllocation, FillsAFourChannelCaseStudyTableWithoutAllocating) {
  // GIVEN a 4-channel, 4080-sample recipe with PRBS, multisine and step sources, and
  // table and scratch storage prepared beforehand
  auto recipe = testing::mixed_case_study_recipe();
  std::vector<double> table(4 * 4080);
  std::vector<double> scratch(scratch_size(*recipe));
  // WHEN the table is generated
  const long before = g_allocations.load();
  const Status status = generate(*recipe, {table.data(), 4, 4080}, scratch);
  const Status block = generate_block(*recipe, 1234, {table.data(), 4, 100}, scratch);
  const long during = g_allocations.load() - before;
  // THEN nothing was allocated, and the counter does see allocations
  EXPECT_TRUE(status) << status.message();
  EXPECT_TRUE(block) << block.message();
  EXPECT_EQ(during, 0);
  auto probe = std::make_unique<int>(1);
  EXPECT_GT(g_allocations.load() - before, during);
}

}  // namespace
}  // namespace excite::signal
