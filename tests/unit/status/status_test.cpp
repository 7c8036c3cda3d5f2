// SPDX-License-Identifier: MIT
// The one status vocabulary: codes, names, the message and its bounds.
#include "base/status/status.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <set>
#include <string>
#include <type_traits>

#include "excite/hal/status.hpp"
#include "firmware/signal/status.hpp"

namespace excite {
namespace {

// One vocabulary: the hal's status and the firmware core's are the same type.
static_assert(std::is_same_v<hal::StatusCode, StatusCode>);
static_assert(std::is_same_v<signal::StatusCode, StatusCode>);
static_assert(std::is_same_v<signal::Status, Status>);
static_assert(std::string_view(to_string(hal::StatusCode::timeout)) == "timeout");

TEST(Status, EveryCodeHasItsOwnName) {
  std::set<std::string> names;
  for (int c = 0; c <= static_cast<int>(StatusCode::io_error); ++c) {
    const std::string name = to_string(static_cast<StatusCode>(c));
    EXPECT_NE(name, "unknown") << c;
    EXPECT_TRUE(names.insert(name).second) << name;
  }
}

TEST(Status, OkHasNoMessage) {
  const Status ok;
  EXPECT_TRUE(ok.is_ok());
  EXPECT_STREQ(ok.message(), "");
}

TEST(Status, FieldErrorIsInTheOneForm) {
  const Status s = Status::field_error(StatusCode::invalid_field, "channels", "9", "1..8");
  EXPECT_EQ(s.code(), StatusCode::invalid_field);
  EXPECT_STREQ(s.message(), "channels = 9, expected 1..8");
}

TEST(Status, OkIsNotAnErrorCode) {
  const Status s = Status::error(StatusCode::ok, "x = 1, expected 2");
  EXPECT_EQ(s.code(), StatusCode::invalid_field);
}

TEST(Status, LongMessagesAreCutAndTerminated) {
  const std::string field(400, 'f');
  const Status s = Status::field_error(StatusCode::invalid_field, field.c_str(), "1", "2");
  EXPECT_EQ(std::strlen(s.message()), Status::kMessageCapacity - 1);
}

}  // namespace
}  // namespace excite
