// SPDX-License-Identifier: MIT
// Issue 40 §5: what the commands read is bounded and checked, and what they say is the one
// message form, printable: a model file that is /dev/zero, a FIFO or too large is refused
// naming the file; an output that is any input (--structures-from's too) is refused; a run
// of more channels than a model file holds is refused before any fit; an escape sequence in
// a file name reaches the terminal escaped; "-hist.csv" is an unknown option, not -h.

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>

#include "cli_process.hpp"

namespace {

namespace fs = std::filesystem;
using excite_cli_test::bytes_of;
using excite_cli_test::excite;
using excite_cli_test::ExciteCli;
using excite_cli_test::Result;

using excite_cli_test::contains;

using InputHygiene = ExciteCli;

TEST_F(InputHygiene, ModelFilesAreRegularFilesOfBoundedSize) {
  Result r = excite("export /dev/zero --format json -o " + path("x.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "/dev/zero: file type = character device, expected a regular "
                       "file (a model file from excite identify -o)"))
      << r.out;
  ASSERT_EQ(::mkfifo(path("fifo.json").c_str(), 0600), 0);
  r = excite_cli_test::shell("timeout 20 " + std::string(EXCITE_CLI) + " export " +
                             path("fifo.json") + " --format json -o " + path("x.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;  // 124: it waited on the FIFO
  EXPECT_TRUE(contains(r.out, "fifo.json: file type = FIFO, expected a regular file")) << r.out;
  {
    std::ofstream big(path("big.json"));
    big << "{\"format\":\"excite model v2\",\"pad\":\"" << std::string(33 << 20, 'x') << "\"}";
  }
  r = excite("export " + path("big.json") + " --format json -o " + path("x.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "big.json: size = 34603045 bytes, expected at most 33554432 bytes"))
      << r.out;
  EXPECT_FALSE(fs::exists(path("x.json")));
}

// identify RUN --structures-from M -o M replaced its own input.
TEST_F(InputHygiene, AnOutputThatIsAnyInputIsRefused) {
  ASSERT_EQ(
      excite("design -q --plant woodberry2x2 --preset prbsUnc -o " + path("p.plan")).exit_code, 0);
  ASSERT_EQ(excite("simulate " + path("p.plan") + " --plant woodberry2x2 --noise-var 5e-4 -o " +
                   path("run.csv"))
                .exit_code,
            0);
  ASSERT_EQ(excite("identify " + path("run.csv") + " -o " + path("m.json")).exit_code, 0);
  const std::string model = bytes_of(path("m.json"));
  const Result r = excite("identify " + path("run.csv") + " --structures-from " + path("m.json") +
                          " -o " + path("m.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "cannot be written (it is the input ")) << r.out;
  EXPECT_EQ(bytes_of(path("m.json")), model);
}

// A run log of 65 inputs, long enough to identify: refused before any fit (it took 77 s and
// wrote a model no other
// command reads).
TEST_F(InputHygiene, IdentifyRefusesMoreChannelsThanAModelFileHolds) {
  {
    std::ofstream log(path("wide.csv"));
    log << "# excite run log v3\n# producer: test\n# plant: wide\n# plan: none\n"
        << "# sample_time_min: 1\n# tau_high_min: 10\n# beta: 3\n# switch_time_min: 5\n# inputs:";
    for (int i = 1; i <= 65; ++i) log << " u" << i;
    log << "\n# outputs: y1\n# units:";
    for (int i = 1; i <= 65; ++i) log << " u" << i << "=-";
    log << " y1=-\nt_min,k";
    for (int i = 1; i <= 65; ++i) log << ",du_u" << i;
    for (int i = 1; i <= 65; ++i) log << ",u_u" << i;
    log << ",dy_y1,flags,state,segment\n";
    for (int k = 0; k < 2700; ++k) {  // enough rows for identify to fit 65 inputs
      log << k << ',' << k;
      for (int pass = 0; pass < 2; ++pass) {
        for (int i = 1; i <= 65; ++i) log << ',' << (((k / (i + 2)) % 2) != 0 ? 0.1 : -0.1);
      }
      log << ',' << std::sin(k * 0.1) << ",0,running,0\n";
    }
  }
  const Result r = excite("identify " + path("wide.csv") + " -o " + path("m.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "wide.csv: inputs = 65 channels, expected at most 64")) << r.out;
  EXPECT_FALSE(fs::exists(path("m.json")));
}

// An escape sequence in a name reaches the terminal escaped, in our messages and CLI11's.
TEST_F(InputHygiene, EscapeSequencesInMessagesArePrintedEscaped) {
  const std::string name = path("m\x1b[2J\x1b[31m.json");
  std::ofstream(name) << "{\"format\": 1}";
  Result r = excite("export '" + name + "' --format json -o " + path("x.json"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
  EXPECT_TRUE(contains(r.out, "m\\x1b[2J\\x1b[31m.json: format, expected")) << r.out;
  r = excite("export '" + path("gone\x1b[31m.json") + "' --format json -o " + path("x.json"));
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
  EXPECT_TRUE(contains(r.out, "gone\\x1b[31m.json")) << r.out;
}

// "-hist.csv" read as -h -i -s … printed the help and exited 0.
TEST_F(InputHygiene, ADashNameIsAnUnknownOptionNotHelp) {
  const Result r = excite("import -hist.csv");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_TRUE(contains(r.out, "excite: error: option = -hist.csv, expected a known option"))
      << r.out;
  EXPECT_FALSE(contains(r.out, "Usage:")) << r.out;
  EXPECT_EQ(excite("import -h").exit_code, 0);
}

// A long export without its header row took its first sample as the header (and lost it);
// UTF-16 and UTF-32 exports were refused as "tag not found" among columns of zero bytes.
TEST_F(InputHygiene, ImportSaysWhatIsWrongWithTheFilesShape) {
  std::string rows;
  for (int k = 0; k < 60; ++k) {
    char time[32];
    std::snprintf(time, sizeof time, "2026-01-01 %02d:%02d:00", k / 60, k % 60);
    rows += "FC101," + std::string(time) + "," + std::to_string(k % 2) + "\n";
    rows += "TI205," + std::string(time) + "," + std::to_string(0.01 * k) + "\n";
  }
  std::ofstream(path("long.csv")) << rows;
  Result r = excite("import " + path("long.csv") +
                    " --long --mv FC101 --cv TI205 --sample-time-min 1 -o " + path("o.csv"));
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "long.csv:1: header = 'FC101', '2026-01-01 00:00:00', '0' (3 "
                       "columns), expected column names TAG,TIME,VALUE[,QUALITY] (--long): "
                       "this row reads as a sample"))
      << r.out;
  std::ofstream(path("long.csv")) << "tag,time,value\n" << rows;
  r = excite("import " + path("long.csv") +
             " --long --mv FC101 --cv TI205 --sample-time-min 1 -o " + path("o.csv"));
  EXPECT_EQ(r.exit_code, 0) << r.out;

  const std::string text = "time,FC101,TI205\n2026-01-01 00:00:00,1,2\n";
  std::string utf16le = "\xFF\xFE", utf16, utf32le = std::string("\xFF\xFE\0\0", 4);
  for (const char c : text) {
    utf16le += std::string{c, '\0'};
    utf16 += std::string{c, '\0'};
    utf32le += std::string{c, '\0', '\0', '\0'};
  }
  for (const auto& [name, bytes, encoding] :
       {std::tuple{"u16.csv", utf16le, "UTF-16LE (byte order mark FF FE)"},
        std::tuple{"u16n.csv", utf16, "UTF-16 (no byte order mark)"},
        std::tuple{"u32.csv", utf32le, "UTF-32LE (byte order mark FF FE 00 00)"}}) {
    std::ofstream(path(name), std::ios::binary) << bytes;
    r = excite("import " + path(name) + " --mv FC101 --cv TI205 --sample-time-min 1 -o " +
               path("o2.csv"));
    EXPECT_EQ(r.exit_code, 1) << r.out;
    EXPECT_TRUE(contains(
        r.out, std::string(name) + ":1: encoding = " + encoding + ", expected UTF-8 or ASCII text"))
        << r.out;
  }
}

}  // namespace
