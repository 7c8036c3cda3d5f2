// SPDX-License-Identifier: MIT
#pragma once
// Link excite_test_counting_malloc into a test and every call of malloc, calloc, realloc,
// aligned_alloc, posix_memalign and memalign in the process is counted (interposed,
// forwarding to glibc's __libc_* functions). Together with excite_test_counting_new
// (operator new) it proves "no allocation" (STYLE.md practice 5).
// Under AddressSanitizer the interposition is compiled out (ASan owns malloc);
// malloc_interposed() then says false and only operator new is counted.

namespace excite::test {

/// malloc-family calls since the process started.
long mallocs();

/// False when the interposition is compiled out (sanitizer builds).
bool malloc_interposed();

}  // namespace excite::test
