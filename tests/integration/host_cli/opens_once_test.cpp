// SPDX-License-Identifier: MIT
// Issue 38 §1: `excite identify` opens each run log once — the row and value limits are the
// reader's, enforced while it reads (firmware/runlog ReadOptions), not a count before it
// (before: three opens, counted, counted again, read). The opens are counted by an
// LD_PRELOAD shim (tests/support/counting_opens.cpp) around the real program.

#include <gtest/gtest.h>

#include <string>

#include "cli_process.hpp"

namespace {

namespace cli = excite_cli_test;
using cli::Result;

class OpensOnce : public cli::ExciteCli {
 protected:
  void make_run(const char* name) {
    ASSERT_EQ(cli::excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan"))
                  .exit_code,
              0);
    ASSERT_EQ(cli::excite("simulate " + path("wb.plan") +
                          " --plant woodberry2x2 --noise-var 5e-4 -o " + path(name))
                  .exit_code,
              0);
  }
  // How often `excite ARGS` opened `file`, the run's result in `r`. ASan's runtime must come
  // first among the preloaded libraries unless told otherwise (the asan preset).
  int opens_of(const std::string& file, const std::string& args, Result& r) {
    r = cli::shell("EXCITE_COUNT_OPENS_OF='" + file + "' EXCITE_COUNT_OPENS_TO='" +
                   path("opens.txt") + "' LD_PRELOAD='" + EXCITE_COUNTING_OPENS +
                   "' ASAN_OPTIONS=\"${ASAN_OPTIONS:+$ASAN_OPTIONS:}verify_asan_link_order=0\" " +
                   EXCITE_CLI + " " + args);
    const std::string count = cli::bytes_of(path("opens.txt"));
    return count.empty() ? -1 : std::stoi(count);
  }
};

TEST_F(OpensOnce, IdentifyOpensItsRunLogOnce) {
  make_run("wb.csv");
  Result r;
  EXPECT_EQ(opens_of(path("wb.csv"), "identify " + path("wb.csv"), r), 1) << r.out;
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

TEST_F(OpensOnce, IdentifyOpensEachPooledRunOnce) {
  make_run("a.csv");
  ASSERT_EQ(cli::shell("cp " + path("a.csv") + " " + path("b.csv")).exit_code, 0);
  Result r;
  EXPECT_EQ(opens_of(path("b.csv"), "identify " + path("a.csv") + " " + path("b.csv"), r), 1)
      << r.out;
  EXPECT_EQ(r.exit_code, 0) << r.out;
}

// The shim itself counts: the same log named twice is opened twice.
TEST_F(OpensOnce, TheCounterSeesEveryOpen) {
  make_run("wb.csv");
  Result r;
  EXPECT_EQ(opens_of(path("wb.csv"), "identify " + path("wb.csv") + " " + path("wb.csv"), r), 2)
      << r.out;
}

}  // namespace
