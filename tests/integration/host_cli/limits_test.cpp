// SPDX-License-Identifier: MIT
// Issue 11 item 3: bounded work and memory with a clear error, options that refuse NaN and
// negatives by name, input checks with file, row and column; issue 13 item 4: --version on
// every program (host/README.md, "Limits").

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "cli_process.hpp"
#include "firmware/plan/codec.hpp"

namespace {

using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;
using excite_cli_test::shell;
namespace fs = std::filesystem;

using excite_cli_test::contains;

class Limits : public ExciteCli {
 protected:
  void make_plan_and_run() {
    ASSERT_EQ(
        excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code,
        0);
    ASSERT_EQ(excite("simulate " + path("wb.plan") + " --plant woodberry2x2 --noise-var 5e-4 -o " +
                     path("wb.csv"))
                  .exit_code,
              0);
  }
};

TEST_F(Limits, EveryProgramPrintsItsVersion) {
  // EXCITE_VERSION: the project's version (firmware/runlog/format.hpp kVersion).
  for (const auto& [program, name] :
       {std::pair{EXCITE_CLI, "excite"}, std::pair{EXCITE_PLANT, "excite-plant"},
        std::pair{EXCITE_GATEWAY, "excite-gateway"}}) {
    const Result r = shell(std::string(program) + " --version");
    EXPECT_EQ(r.exit_code, 0) << name;
    EXPECT_EQ(r.out, std::string(name) + " " + EXCITE_VERSION + "\n") << name;
  }
}

TEST_F(Limits, NanAndNegativeOptionValuesAreRefusedByName) {
  make_plan_and_run();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"simulate " + path("wb.plan") + " --plant woodberry2x2 --noise-var nan -o " + path("n.csv"),
       "--noise-var: nan, expected a finite number >= 0"},
      {"simulate " + path("wb.plan") + " --plant woodberry2x2 --noise-var -1 -o " + path("n.csv"),
       "--noise-var: -1, expected a finite number >= 0"},
      {"gains --plant woodberry2x2 --xi-threshold nan", "--xi-threshold: nan, expected"},
      {"gains --plant woodberry2x2 --xi-threshold -1", "--xi-threshold: -1, expected"},
      {"identify --max-delay 0 " + path("wb.csv"), "--max-delay: 0, expected"},
      {"identify --tau-high inf " + path("wb.csv"), "--tau-high: inf, expected"},
      {"campaign --plant woodberry2x2 --noise-var nan -o " + path("c"), "--noise-var: nan"},
      {"campaign --plant woodberry2x2 --structure three_poles -o " + path("c"),
       "--structure: three_poles not in {auto,first_order,two_poles,"},
      {"loop-config --plant woodberry2x2 --input-range nan -o " + path("l"), "--input-range: nan"},
  };
  for (const auto& [args, message] : cases) {
    const Result r = excite(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, message)) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(path("n.csv")));
  const Result plant =
      shell(std::string(EXCITE_PLANT) + " --plant woodberry2x2 --sample-time-s nan");
  EXPECT_EQ(plant.exit_code, 2) << plant.out;
  EXPECT_TRUE(contains(plant.out, "--sample-time-s = nan")) << plant.out;
}

// 99,999 Schroeder lines took 73 s before they were refused; now the sizes come first: the
// message below is the spec check's, which runs before any line is synthesised (a clock
// would only measure the machine: issue 46).
TEST_F(Limits, OversizedMultisineSpecIsRefusedBeforeSynthesis) {
  const auto spec = [&](const char* period, const char* last_line) {
    std::ofstream(path("ms.toml"))
        << "design = \"multisine\"\n[prior]\ninputs = 1\n"
           "sample_time_min = 1.0\n[[input]]\nname = \"u\"\n"
           "amplitude = 1.0\nmin = -1.0\nmax = 1.0\n[multisine]\n"
           "period = "
        << period << "\nfirst_line = 1\nlast_line = " << last_line << "\nphases = \"schroeder\"\n";
  };
  spec("200000", "99999");
  const Result lines = excite("design " + path("ms.toml") + " -o " + path("ms.plan"));
  EXPECT_EQ(lines.exit_code, 1);
  EXPECT_TRUE(contains(lines.out, "99999 lines, expected at most 4096")) << lines.out;
  spec("300000", "100");
  const Result table = excite("design " + path("ms.toml") + " -o " + path("ms.plan"));
  EXPECT_EQ(table.exit_code, 1);
  EXPECT_TRUE(contains(table.out, "= 300000 values, expected at most 262144")) << table.out;
  EXPECT_FALSE(fs::exists(path("ms.plan")));
}

// A plan whose table the gateway could not hold (8·10⁷ samples took inspect 1.3 GB).
TEST_F(Limits, PlanBeyondTheGatewaysTableIsRefusedByInspectAndSimulate) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  const std::string bytes = bytes_of(path("wb.plan"));
  excite::plan::Plan plan;
  ASSERT_TRUE(excite::plan::decode(
      {reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()}, plan));
  plan.recipe.samples = 80'000'000;
  std::vector<std::uint8_t> out(excite::plan::max_encoded_size());
  const auto encoded = excite::plan::encode(plan, out);
  ASSERT_TRUE(encoded.status) << encoded.status.message();
  std::ofstream(path("huge.plan"), std::ios::binary)
      .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(encoded.size));
  for (const std::string& args :
       {"inspect " + path("huge.plan"),
        "simulate " + path("huge.plan") + " --plant woodberry2x2 -o " + path("h.csv")}) {
    const Result r = excite(args);
    EXPECT_EQ(r.exit_code, 1) << args;
    EXPECT_TRUE(contains(r.out,
                         "channels x samples = 2 x 80000000 = 160000000 values, expected "
                         "at most 262144"))
        << r.out;
  }
}

// --periods 100000 wrote 6.4 GB.
TEST_F(Limits, SimulationLongerThanTheRowLimitIsRefusedAndWritesNothing) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("wb.plan")).exit_code, 0);
  const Result r = excite("simulate " + path("wb.plan") +
                          " --plant woodberry2x2 --periods 100000 -o " + path("big.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, "rows, expected at most 100000 (host/README.md, Limits)")) << r.out;
  EXPECT_FALSE(fs::exists(path("big.csv")));
}

// identify on 10⁷ rows threw bad_alloc; the rows are counted before the file is loaded.
TEST_F(Limits, RunLongerThanTheRowLimitIsRefusedByName) {
  make_plan_and_run();
  std::string text = bytes_of(path("wb.csv"));
  const std::string last = text.substr(text.rfind('\n', text.size() - 2) + 1);
  {
    std::ofstream out(path("long.csv"), std::ios::binary);
    out << text;
    for (int i = 0; i < 100'001; ++i) out << last;
  }
  for (const char* command : {"identify ", "balance --plant woodberry2x2 "}) {
    const Result r = excite(command + path("long.csv"));
    EXPECT_EQ(r.exit_code, 1) << command;
    EXPECT_TRUE(
        contains(r.out, path("long.csv") + ": more than 100000 data rows, expected at most 100000"))
        << r.out;
  }
}

// One cell of 1e308 made identify fail with "Td = -nan", naming nothing.
TEST_F(Limits, HugeValueInARunIsRefusedWithFileRowAndColumn) {
  make_plan_and_run();
  std::string text = bytes_of(path("wb.csv"));
  // Data row 3 (k = 2): its last dy field (the one before flags) becomes 1e308.
  std::size_t line_start = 0;
  {
    std::size_t pos = 0;
    int data_rows = 0;
    while ((pos = text.find('\n', pos)) != std::string::npos) {
      ++pos;
      if (pos < text.size() && text[pos] != '#' && text.compare(pos, 5, "t_min") != 0 &&
          ++data_rows == 3) {
        line_start = pos;
        break;
      }
    }
  }
  ASSERT_GT(line_start, 0U);
  const std::size_t line_end = text.find('\n', line_start);
  // v3 rows end in ...,dy_last,flags,state,segment: the last dy is before the third-last comma.
  const std::size_t segment_comma = text.rfind(',', line_end);
  const std::size_t state_comma = text.rfind(',', segment_comma - 1);
  const std::size_t flags_comma = text.rfind(',', state_comma - 1);
  const std::size_t dy_comma = text.rfind(',', flags_comma - 1);
  text.replace(dy_comma + 1, flags_comma - dy_comma - 1, "1e308");
  std::ofstream(path("bad.csv"), std::ios::binary) << text;
  const Result r = excite("identify " + path("bad.csv"));
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(contains(r.out, path("bad.csv") + ": data row 3 (k = 2), column dy_")) << r.out;
  EXPECT_TRUE(contains(r.out, "= 1e+308, expected |value| <= 1e+12")) << r.out;
}

// A model whose channels are not the run's used to give a fit anyway.
TEST_F(Limits, ValidateRefusesAModelWithOtherChannels) {
  make_plan_and_run();
  ASSERT_EQ(excite("identify -o " + path("m.json") + " " + path("wb.csv")).exit_code, 0);
  auto model = nlohmann::json::parse(bytes_of(path("m.json")));
  std::swap(model["inputs"][0], model["inputs"][1]);
  std::ofstream(path("swapped.json")) << model.dump();
  const Result r = excite("validate " + path("swapped.json") + " " + path("wb.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "inputs = [")) << r.out;
  EXPECT_TRUE(contains(r.out, "expected the same channels in the same order")) << r.out;
  EXPECT_EQ(excite("validate " + path("m.json") + " " + path("wb.csv")).exit_code, 0);
  // crossval: every run must have the first run's channels (input u1 renamed w1 in the header).
  std::string run = bytes_of(path("wb.csv"));
  const std::size_t header_end = run.find('\n', run.find("t_min,"));
  ASSERT_NE(header_end, std::string::npos);
  for (std::size_t at = run.find("u1"); at < header_end; at = run.find("u1", at)) run[at] = 'w';
  std::ofstream(path("other.csv"), std::ios::binary) << run;
  const Result cv = excite("crossval " + path("wb.csv") + " " + path("other.csv"));
  EXPECT_EQ(cv.exit_code, 1) << cv.out;
  EXPECT_TRUE(contains(cv.out, path("other.csv") + ": inputs = [w1, u2]")) << cv.out;
}

// balance --gain with a 2×3, an all-zero or a singular matrix exited 0 and printed inf.
TEST_F(Limits, BalanceRefusesAGainOfTheWrongShapeOrRank) {
  make_plan_and_run();
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[[1, 2, 3], [4, 5, 6]]", "gain is 2 x 3, " + path("wb.csv") + " has 2 outputs x 2 inputs"},
      {"[[0, 0], [0, 0]]", "gain is singular"},
      {"[[1, 2], [2, 4]]", "gain is singular"},
  };
  for (const auto& [gain, message] : cases) {
    std::ofstream(path("g.json")) << "{\"gain\": " << gain << "}";
    const Result r = excite("balance --gain " + path("g.json") + " " + path("wb.csv"));
    EXPECT_EQ(r.exit_code, 1) << gain << "\n" << r.out;
    EXPECT_TRUE(contains(r.out, message)) << gain << "\n" << r.out;
    EXPECT_FALSE(contains(r.out, "inf")) << r.out;
  }
  std::ofstream(path("g.json")) << "{\"gain\": [[12.8, -18.9], [6.6, -19.4]]}";
  EXPECT_EQ(excite("balance --gain " + path("g.json") + " " + path("wb.csv")).exit_code, 0);
}

TEST_F(Limits, MessagesNameThePathAndPrintNumbersShort) {
  for (const std::string& args : {"inspect " + dir_.string(), "identify " + dir_.string(),
                                  "validate " + dir_.string() + " " + dir_.string(),
                                  "balance --gain " + dir_.string() + " " + dir_.string()}) {
    const Result dir = excite(args);
    EXPECT_EQ(dir.exit_code, 1) << args;
    EXPECT_TRUE(contains(dir.out, "excite: error: " + dir_.string() + ": is a directory, expected"))
        << dir.out;
  }
  std::ofstream(path("spec.toml")) << "design = \"multisine\"\n[prior]\ninputs = 1\n"
                                      "sample_time_min = 1.0\n[[input]]\nname = \"u\"\n"
                                      "amplitude = 1.5e308\nmin = -1e308\nmax = 1e308\n"
                                      "[multisine]\nperiod = 256\nfirst_line = 1\n"
                                      "last_line = 31\n";
  const Result range = excite("design " + path("spec.toml") + " -o " + path("x.plan"));
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_TRUE(contains(range.out, "(0, 1e+308]")) << range.out;
  EXPECT_LT(range.out.size(), 300U) << range.out;
  // -o naming a file: refused before any design runs (no "[1/17]" progress line: the
  // campaign says one after each experiment, the first after the first).
  std::ofstream(path("file")) << "x";
  const Result camp = excite("campaign --plant woodberry2x2 -o " + path("file"));
  EXPECT_FALSE(contains(camp.out, "[1/")) << camp.out;
  EXPECT_EQ(camp.exit_code, 1);
  EXPECT_TRUE(contains(camp.out, path("file"))) << camp.out;
}

}  // namespace
