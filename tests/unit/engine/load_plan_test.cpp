// SPDX-License-Identifier: MIT
// Start-up: plan file → table. Refusals name what was found; the table is bit-identical to
// the host's preview (host::make_table, the same signal core).
#include "firmware/engine/load_plan.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "../plan/example_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"
#include "host/design/table.hpp"

namespace excite::engine {
namespace {

using signal::Status;
using signal::StatusCode;

std::vector<std::uint8_t> encoded(const plan::Plan& p) {
  std::vector<std::uint8_t> out(plan::max_encoded_size());
  const plan::EncodeResult r = plan::encode(p, out);
  EXPECT_TRUE(r.status) << r.status.message();
  out.resize(r.size);
  return out;
}

struct Loaded {
  std::unique_ptr<plan::Plan> plan = std::make_unique<plan::Plan>();
  std::vector<double> storage = std::vector<double>(signal::kTableCapacity);
  signal::TableView table;
};

TEST(LoadPlanTest, TableIsBitIdenticalToTheHostPreview) {
  const auto source = plan::testing::example_plan();
  const auto bytes = encoded(*source);
  Loaded l;
  ASSERT_TRUE(load_plan(bytes, 4, signal::kTableCapacity, *l.plan));
  std::vector<double> scratch(signal::scratch_size(l.plan->recipe));
  const Status s = make_table(*l.plan, l.storage, scratch, l.table);
  ASSERT_TRUE(s) << s.message();

  const host::Table preview = host::make_table(source->recipe);
  ASSERT_EQ(static_cast<std::uint32_t>(preview.rows()), l.table.samples);
  ASSERT_EQ(static_cast<std::uint32_t>(preview.cols()), l.table.channels);
  EXPECT_EQ(std::memcmp(preview.data(), l.table.data, l.table.size() * sizeof(double)), 0);
}

TEST(LoadPlanTest, RefusesAPlanForAnotherChannelCount) {
  const auto bytes = encoded(*plan::testing::example_plan());
  Loaded l;
  const Status s = load_plan(bytes, 3, signal::kTableCapacity, *l.plan);
  EXPECT_FALSE(s);
  EXPECT_STREQ(s.message(), "plan channels = 4, expected 3 (the setpoints of the configuration)");
  EXPECT_EQ(l.plan->recipe.channels, 0U);  // nothing half-loaded
}

TEST(LoadPlanTest, AClosedLoopPlanStreamsOnlyWhereItsExcitationIsWhatTheSetpointsAre) {
  auto setpoint_plan = plan::testing::example_plan();
  setpoint_plan->meta.excitation = plan::Excitation::setpoint;
  const auto bytes = encoded(*setpoint_plan);
  Loaded l;
  EXPECT_FALSE(load_plan(bytes, 4, signal::kTableCapacity, *l.plan));  // never as MV moves
  const Status mv = load_plan(bytes, 4, signal::kTableCapacity, *l.plan, plan::Excitation::mv);
  EXPECT_FALSE(mv);
  EXPECT_NE(std::strstr(mv.message(), "plan excitation = setpoint, expected mv or open_loop"),
            nullptr)
      << mv.message();
  EXPECT_EQ(l.plan->recipe.channels, 0U);  // nothing half-loaded
  EXPECT_TRUE(load_plan(bytes, 4, signal::kTableCapacity, *l.plan, plan::Excitation::setpoint));
  // An open-loop plan streams as offsets too: its table is in the setpoints' units.
  const auto open = encoded(*plan::testing::example_plan());
  EXPECT_TRUE(load_plan(open, 4, signal::kTableCapacity, *l.plan, plan::Excitation::setpoint));
}

TEST(LoadPlanTest, RefusesACorruptFileByChecksum) {
  auto bytes = encoded(*plan::testing::example_plan());
  bytes[40] ^= 0x01;
  Loaded l;
  const Status s = load_plan(bytes, 4, signal::kTableCapacity, *l.plan);
  EXPECT_EQ(s.code(), StatusCode::checksum_mismatch);
}

TEST(LoadPlanTest, RefusesAnotherFormatVersion) {
  auto bytes = encoded(*plan::testing::example_plan());
  bytes[8] = 9;  // version field
  Loaded l;
  const Status s = load_plan(bytes, 4, signal::kTableCapacity, *l.plan);
  EXPECT_EQ(s.code(), StatusCode::unsupported_version);
}

TEST(LoadPlanTest, RefusesATableBeyondTheCapacity) {
  const auto bytes = encoded(*plan::testing::example_plan());
  Loaded l;
  const Status s = load_plan(bytes, 4, 100, *l.plan);
  EXPECT_EQ(s.code(), StatusCode::capacity_exceeded);
  EXPECT_NE(std::string(s.message()).find("expected <= 100"), std::string::npos);
}

TEST(LoadPlanTest, RefusesTableValuesOutsideThePlanLimits) {
  auto source = plan::testing::example_plan();
  source->meta.channels[2].min = -0.001;  // the table goes further
  source->meta.channels[2].max = 0.001;
  const auto bytes = encoded(*source);
  Loaded l;
  ASSERT_TRUE(load_plan(bytes, 4, signal::kTableCapacity, *l.plan));
  std::vector<double> scratch(signal::scratch_size(l.plan->recipe));
  const Status s = make_table(*l.plan, l.storage, scratch, l.table);
  EXPECT_EQ(s.code(), StatusCode::limit_violated);
  EXPECT_NE(std::string(s.message()).find("side draw S"), std::string::npos) << s.message();
  EXPECT_EQ(l.table.data, nullptr);
}

}  // namespace
}  // namespace excite::engine
