// SPDX-License-Identifier: MIT
// The plan codec allocates nothing (STYLE.md practice 5): this executable links the
// counting operator new of tests/support.
#include <gtest/gtest.h>

#include <vector>

#include "counting_new.hpp"
#include "example_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/plan/limits.hpp"
#include "firmware/signal/generate.hpp"

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
  const long before = excite::test::allocations();
  const EncodeResult encoded = encode(*plan, file);
  const Status decoded_status = decode(std::span(file).first(encoded.size), *decoded);
  const Status generated = signal::generate(decoded->recipe, {table.data(), 4, 4080}, scratch);
  const LimitCheck limits = check_limits(*decoded, {table.data(), 4, 4080});
  file[40] ^= 1U;
  const Status refused = decode(std::span(file).first(encoded.size), *decoded);
  const long during = excite::test::allocations() - before;
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
