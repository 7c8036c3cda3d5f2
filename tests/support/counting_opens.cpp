// SPDX-License-Identifier: MIT
// LD_PRELOAD shim for tests that count how often a program opens one file (issue 38 §1:
// `excite identify` opens each run log once). With EXCITE_COUNT_OPENS_OF=PATH in the
// environment every fopen/open/openat of exactly PATH (as the program spells it) is
// counted; at exit the count is written to EXCITE_COUNT_OPENS_TO. The real functions are
// called through dlsym(RTLD_NEXT): the program behaves as without the shim. A test double
// only because the kernel's own counter (strace, audit) is not on every machine CI uses.

#include <dlfcn.h>
#include <fcntl.h>

#include <atomic>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

std::atomic<int> g_opens{0};

void note(const char* path) {
  static const char* const watched = std::getenv("EXCITE_COUNT_OPENS_OF");
  if (watched != nullptr && path != nullptr && std::strcmp(path, watched) == 0) ++g_opens;
}

template <class Function>
Function real(const char* name) {
  return reinterpret_cast<Function>(::dlsym(RTLD_NEXT, name));
}

// open's mode argument is there only when the flags create a file.
mode_t mode_of(int flags, va_list args) {
  return (flags & O_CREAT) != 0 || (flags & O_TMPFILE) == O_TMPFILE
             ? static_cast<mode_t>(va_arg(args, unsigned))
             : 0;
}

struct ReportAtExit {
  ~ReportAtExit() {
    const char* to = std::getenv("EXCITE_COUNT_OPENS_TO");
    if (to == nullptr) return;
    if (std::FILE* f = std::fopen(to, "w")) {
      std::fprintf(f, "%d\n", g_opens.load());
      std::fclose(f);
    }
  }
} report_at_exit;

}  // namespace

extern "C" {

std::FILE* fopen(const char* path, const char* mode) {
  note(path);
  static const auto f = real<std::FILE* (*)(const char*, const char*)>("fopen");
  return f(path, mode);
}

std::FILE* fopen64(const char* path, const char* mode) {
  note(path);
  static const auto f = real<std::FILE* (*)(const char*, const char*)>("fopen64");
  return f(path, mode);
}

int open(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  note(path);
  static const auto f = real<int (*)(const char*, int, ...)>("open");
  return f(path, flags, mode);
}

int open64(const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  note(path);
  static const auto f = real<int (*)(const char*, int, ...)>("open64");
  return f(path, flags, mode);
}

int openat(int dir, const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  note(path);
  static const auto f = real<int (*)(int, const char*, int, ...)>("openat");
  return f(dir, path, flags, mode);
}

int openat64(int dir, const char* path, int flags, ...) {
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  note(path);
  static const auto f = real<int (*)(int, const char*, int, ...)>("openat64");
  return f(dir, path, flags, mode);
}

}  // extern "C"
