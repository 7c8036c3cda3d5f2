// SPDX-License-Identifier: MIT
// Issue 19 item 3: an output means exactly what was asked (host/README.md, "Output files"):
// /dev/stdout is written through the descriptor the shell opened (`>>` appends, a pipe
// works); with the data on standard output every human line goes to stderr; an output that
// is one of the inputs is refused and the input left as it was.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "cli_process.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;
using excite_cli_test::shell;
namespace fs = std::filesystem;

using excite_cli_test::contains;

class OutputMeaning : public ExciteCli {
 protected:
  void SetUp() override {
    ExciteCli::SetUp();
    ::setenv("SOURCE_DATE_EPOCH", "1700000000", 1);  // byte-identical plans
  }
  void TearDown() override {
    ::unsetenv("SOURCE_DATE_EPOCH");
    ExciteCli::TearDown();
  }
  std::string cli() const { return EXCITE_CLI; }
  // A plan, its run, its model and a small historian export (MV1, CV1).
  void make_inputs() {
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("p.plan")).exit_code,
        0);
    ASSERT_EQ(excite("simulate " + path("p.plan") + " --plant woodberry2x2 -o " + path("run.csv"))
                  .exit_code,
              0);
    ASSERT_EQ(excite("identify " + path("run.csv") + " -o " + path("model.json")).exit_code, 0);
    std::ofstream h(path("h.csv"));
    h << "time,MV1,CV1\n";
    for (int k = 0; k < 50; ++k) {
      h << "2024-01-01T00:" << (k < 10 ? "0" : "") << k << ":00," << 1 + (k / 10) % 2 << ','
        << 2.0 + 0.1 * k << '\n';
    }
  }
};

// The old code resolved /proc/self/fd/1 by hand and renamed a new file over the journal.
TEST_F(OutputMeaning, DevStdoutAppendedToAJournalAppends) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("p.plan")).exit_code, 0);
  const std::string plan = bytes_of(path("p.plan"));
  std::ofstream(path("journal.log")) << "journal line\n";
  const Result r =
      shell(cli() + " design --plant woodberry2x2 --preset prbsUnc -o /dev/stdout >> " +
            path("journal.log"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(bytes_of(path("journal.log")), "journal line\n" + plan);
  EXPECT_TRUE(contains(r.out, "wrote /dev/stdout")) << r.out;  // the human line: on stderr
}

// Through a pipe: the old code took "pipe:[…]" for a file name and failed.
TEST_F(OutputMeaning, DevStdoutThroughAPipeWorks) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("p.plan")).exit_code, 0);
  const Result r = shell("{ " + cli() +
                         " design -q --plant woodberry2x2 --preset prbsUnc -o /dev/stdout; echo "
                         "$? > " +
                         path("rc") + "; } | cat > " + path("copy.plan"));
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_EQ(bytes_of(path("rc")), "0\n");
  EXPECT_EQ(bytes_of(path("copy.plan")), bytes_of(path("p.plan")));
}

// `-o -`: stdout carries the data alone, whatever the command prints for a human.
TEST_F(OutputMeaning, DashKeepsHumanTextOffTheData) {
  make_inputs();
  const auto stdout_of = [&](const std::string& args, const std::string& file) {
    const Result r =
        shell(cli() + " " + args + " -o - 2>" + path("err.txt") + " >" + path(file.c_str()));
    EXPECT_EQ(r.exit_code, 0) << args << "\n" << bytes_of(path("err.txt"));
    return bytes_of(path(file.c_str()));
  };
  EXPECT_EQ(stdout_of("design --plant woodberry2x2 --preset prbsUnc", "d.plan"),
            bytes_of(path("p.plan")));
  EXPECT_TRUE(contains(bytes_of(path("err.txt")), "wrote -:"));
  EXPECT_EQ(stdout_of("simulate " + path("p.plan") + " --plant woodberry2x2", "s.csv"),
            bytes_of(path("run.csv")));
  EXPECT_TRUE(contains(bytes_of(path("err.txt")), "wrote -:"));
  const std::string model = stdout_of("identify " + path("run.csv"), "m.json");
  EXPECT_TRUE(nlohmann::json::accept(model)) << model.substr(0, 300);
  EXPECT_TRUE(contains(bytes_of(path("err.txt")), "identified G(0)"));
  EXPECT_TRUE(nlohmann::json::accept(
      stdout_of("export " + path("model.json") + " --format json", "e.json")));
  const std::string run = stdout_of("import " + path("h.csv") + " --mv MV1 --cv CV1", "i.csv");
  EXPECT_FALSE(contains(run, "wrote")) << run;
  EXPECT_TRUE(contains(bytes_of(path("err.txt")), "MV MV1 -> MV1"));
  ASSERT_EQ(excite("import " + path("h.csv") + " --mv MV1 --cv CV1 -o " + path("i2.csv")).exit_code,
            0);
  EXPECT_EQ(run, bytes_of(path("i2.csv")));
  // --json and -o - would put two documents on one stream: refused.
  const Result both = excite("identify --json " + path("run.csv") + " -o -");
  EXPECT_EQ(both.exit_code, 1);
  EXPECT_TRUE(contains(both.out, "both write to standard output")) << both.out;
}

// An output that is one of the inputs (by name, or by a link to it) is refused and the input
// stays as it was; the old code replaced it.
TEST_F(OutputMeaning, OutputThatIsAnInputIsRefused) {
  make_inputs();
  fs::create_symlink("run.csv", path("link.csv"));
  struct Case {
    std::string args, victim;
  };
  for (const Case& c :
       {Case{"identify " + path("run.csv") + " -o " + path("run.csv"), "run.csv"},
        Case{"identify " + path("run.csv") + " -o " + path("link.csv"), "run.csv"},
        Case{"simulate " + path("p.plan") + " --plant woodberry2x2 -o " + path("p.plan"), "p.plan"},
        Case{"export " + path("model.json") + " --format json -o " + path("model.json"),
             "model.json"},
        Case{"import " + path("h.csv") + " --mv MV1 --cv CV1 -o " + path("h.csv"), "h.csv"}}) {
    const std::string before = bytes_of(path(c.victim.c_str()));
    const Result r = excite(c.args);
    EXPECT_EQ(r.exit_code, 1) << c.args << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, "cannot be written (it is the input ")) << c.args << "\n" << r.out;
    EXPECT_EQ(bytes_of(path(c.victim.c_str())), before) << c.args;
  }
}

}  // namespace
