// SPDX-License-Identifier: MIT
#pragma once
// Link excite_test_counting_new into a test or bench executable and every global
// operator new (all forms) is counted. Usage:
//   const long before = excite::test::allocations();
//   … code that must not allocate …
//   EXPECT_EQ(excite::test::allocations() - before, 0);

namespace excite::test {

/// Allocations through the global operator new since the process started.
long allocations();

}  // namespace excite::test
