// SPDX-License-Identifier: MIT
#pragma once
// The harnesses' one assertion: a property that must hold for every input. A violation
// prints what broke and aborts, which libFuzzer reports as a crash and saves the input.

#include <cstdio>
#include <cstdlib>

namespace excite::fuzz {

[[noreturn]] inline void fail(const char* what, const char* file, int line) {
  std::fprintf(stderr, "%s:%d: fuzz property violated: %s\n", file, line, what);
  std::abort();
}

}  // namespace excite::fuzz

#define EXCITE_FUZZ_CHECK(condition, what) \
  ((condition) ? static_cast<void>(0) : ::excite::fuzz::fail(what, __FILE__, __LINE__))
