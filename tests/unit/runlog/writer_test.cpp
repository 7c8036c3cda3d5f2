// SPDX-License-Identifier: MIT
#include "firmware/runlog/writer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <new>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"

// Every operator new of this test program is counted, to prove that formatting allocates
// nothing (STYLE.md practice 5).
namespace {
std::atomic<long> g_allocations{0};
}  // namespace

// The replacements pair malloc with free by design; GCC cannot see that when it inlines them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}

namespace excite::runlog {
namespace {

constexpr std::array<Channel, 2> kInputs = {{{"L", "kmol/min"}, {"V", "kmol/min"}}};
constexpr std::array<Channel, 1> kOutputs = {{{"xD", "mol/mol"}}};

Header two_by_one() {
  return Header{"column A", "plans/prbs.toml", 1.0, kInputs, kOutputs};
}

std::string text_of(WriteResult r, const std::array<char, 1024>& buf) {
  return std::string(buf.data(), r.length);
}

TEST(RunLogWriter, HeaderListsMagicKeysUnitsAndColumns) {
  std::array<char, 1024> buf{};
  const WriteResult r = format_header(two_by_one(), buf);
  ASSERT_EQ(r.status, WriteStatus::ok);
  EXPECT_EQ(text_of(r, buf),
            "# excite run log v3\n"
            "# plant: column A\n"
            "# plan: plans/prbs.toml\n"
            "# sample_time_min: 1\n"
            "# inputs: L V\n"
            "# outputs: xD\n"
            "# units: L=kmol/min V=kmol/min xD=mol/mol\n"
            "t_min,k,du_L,du_V,u_L,u_V,dy_xD,flags,state,segment\n");
}

TEST(RunLogWriter, ProducerLineNamesTheProgramAndReadsBack) {
  std::array<char, 1024> buf{};
  Header h = two_by_one();
  h.producer = "excite-gateway 0.1.0";
  const WriteResult r = format_header(h, buf);
  ASSERT_EQ(r.status, WriteStatus::ok);
  const std::string text = text_of(r, buf);
  EXPECT_EQ(text.rfind("# excite run log v3\n# producer: excite-gateway 0.1.0\n# plant:", 0), 0U)
      << text;
  const ReadResult back =
      parse_run_log(text + "0,0,0,0,1,1,0,0,armed,0\n1,1,0,0,1,1,0,0,running,0\n", "run.csv");
  ASSERT_TRUE(back.ok()) << back.error->to_string();
  EXPECT_EQ(back.log.producer, "excite-gateway 0.1.0");
  h.producer = "two\nlines";
  EXPECT_EQ(format_header(h, buf).status, WriteStatus::invalid_field);
  EXPECT_FALSE(kVersion.empty());  // CMake's project version reaches the code
}

TEST(RunLogWriter, RowUsesShortestRoundTripNumbers) {
  std::array<char, 1024> buf{};
  const std::array<double, 2> du = {0.1, -0.25};
  const std::array<double, 2> u = {2.806, 3.206};
  const std::array<double, 1> dy = {1.0 / 3.0};
  const WriteResult r = format_row(
      two_by_one(), Row{12.0, 12, du, u, dy, kClamped | kStale, RunState::suspended, 2}, buf);
  ASSERT_EQ(r.status, WriteStatus::ok);
  EXPECT_EQ(text_of(r, buf), "12,12,0.1,-0.25,2.806,3.206,0.3333333333333333,20,suspended,2\n");
}

TEST(RunLogWriter, EveryStateHasItsOwnTextThatReadsBack) {
  std::size_t longest = 0;
  for (std::size_t i = 0; i < kRunStateCount; ++i) {
    const auto state = static_cast<RunState>(i);
    const std::string_view text = to_text(state);
    longest = std::max(longest, text.size());
    RunState back = RunState::unknown;
    ASSERT_TRUE(run_state_from_text(text, back)) << text;
    EXPECT_EQ(back, state) << text;
  }
  EXPECT_EQ(longest, kMaxStateChars);
  RunState s = RunState::running;
  EXPECT_FALSE(run_state_from_text("Running", s));
  EXPECT_FALSE(run_state_from_text("", s));
  EXPECT_EQ(s, RunState::running);
}

TEST(RunLogWriter, ReportsBufferTooSmallInsteadOfTruncating) {
  std::array<char, 1024> big{};
  const std::array<double, 2> du = {0.1, -0.25};
  const std::array<double, 1> dy = {1.0 / 3.0};
  const Row row{0.0, 0, du, du, dy, 0};
  const WriteResult full = format_row(two_by_one(), row, big);
  ASSERT_EQ(full.status, WriteStatus::ok);
  std::array<char, 64> small{};
  const WriteResult r = format_row(two_by_one(), row, std::span(small).first(full.length - 1));
  EXPECT_EQ(r.status, WriteStatus::capacity_exceeded);
  EXPECT_EQ(r.length, 0U);
}

TEST(RunLogWriter, MaxRowCharsHoldsTheWidestNumbers) {
  const std::array<double, 2> du = {-2.2250738585072014e-308, -1.7976931348623157e308};
  const std::array<double, 1> dy = {-4.9406564584124654e-324};
  std::array<char, max_row_chars(2, 1)> buf{};
  const WriteResult r =
      format_row(two_by_one(),
                 Row{-1.2345678901234567e-300, std::numeric_limits<std::uint64_t>::max(), du, du,
                     dy, kKnownFlags, RunState::safe_unconfirmed},
                 buf);
  EXPECT_EQ(r.status, WriteStatus::ok);
}

TEST(RunLogWriter, RejectsNonFiniteWidthAndFlags) {
  std::array<char, 1024> buf{};
  const std::array<double, 2> du = {0.0, std::numeric_limits<double>::quiet_NaN()};
  const std::array<double, 2> ok2 = {0.0, 0.0};
  const std::array<double, 1> dy = {0.0};
  EXPECT_EQ(format_row(two_by_one(), Row{0, 0, du, ok2, dy, 0}, buf).status,
            WriteStatus::bad_argument);
  EXPECT_EQ(format_row(two_by_one(), Row{0, 0, dy, ok2, dy, 0}, buf).status,
            WriteStatus::bad_argument);
  EXPECT_EQ(format_row(two_by_one(), Row{0, 0, ok2, ok2, dy, 1U << 8}, buf).status,
            WriteStatus::bad_argument);
  EXPECT_EQ(
      format_row(two_by_one(), Row{0, 0, ok2, ok2, dy, kSkipped | kDiscontinuity | kBadValue}, buf)
          .status,
      WriteStatus::ok);
  EXPECT_EQ(
      format_row(two_by_one(), Row{0, 0, ok2, ok2, dy, 0, static_cast<RunState>(10)}, buf).status,
      WriteStatus::bad_argument);
}

TEST(RunLogWriter, RefusalsNameTheFieldInTheOneMessageForm) {
  std::array<char, 1024> buf{};
  const std::array<double, 2> ok2 = {0.0, 0.0};
  const std::array<double, 1> dy = {0.0};
  const WriteResult flags = format_row(two_by_one(), Row{0, 0, ok2, ok2, dy, 1U << 8}, buf);
  EXPECT_STREQ(flags.message, "row.flags = (unknown bits), expected bits of Flag only");
  const WriteResult width = format_row(two_by_one(), Row{0, 0, dy, ok2, dy, 0}, buf);
  EXPECT_STREQ(width.message, "row du/u/dy = (wrong width), expected the header's channel counts");
  Header h = two_by_one();
  h.sample_time_min = 0.0;
  EXPECT_STREQ(format_header(h, buf).message,
               "header.sample_time_min = (not finite or <= 0), expected a finite number > 0");
  EXPECT_STREQ(format_row(two_by_one(), Row{0, 0, ok2, ok2, dy, 0}, buf).message, "");
}

TEST(RunLogWriter, RejectsBadHeaders) {
  std::array<char, 1024> buf{};
  Header h = two_by_one();
  h.plant = "two\nlines";
  EXPECT_EQ(format_header(h, buf).status, WriteStatus::invalid_field);
  h = two_by_one();
  h.sample_time_min = 0.0;
  EXPECT_EQ(format_header(h, buf).status, WriteStatus::invalid_field);
  const std::array<Channel, 2> dup = {{{"L", "-"}, {"L", "-"}}};
  h = two_by_one();
  h.inputs = dup;
  EXPECT_EQ(format_header(h, buf).status, WriteStatus::invalid_field);
  const std::array<Channel, 1> comma = {{{"x,D", "-"}}};
  h = two_by_one();
  h.outputs = comma;
  EXPECT_EQ(format_header(h, buf).status, WriteStatus::invalid_field);
}

// Writes a log through a real file and reads it back: every double comes back bit-exact.
TEST(RunLogWriter, FileRoundTripIsExact) {
  char path[] = "/tmp/excite_runlog_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  std::FILE* f = fdopen(fd, "wb");
  ASSERT_NE(f, nullptr);
  std::array<char, 1024> buf{};
  FileWriter w(f, two_by_one(), buf);
  ASSERT_EQ(w.write_header(), WriteStatus::ok);
  std::vector<double> written;
  for (std::uint64_t k = 0; k < 50; ++k) {
    const double x = std::sin(0.37 * static_cast<double>(k)) / 3.0;
    const std::array<double, 2> du = {x, x * 1e-9};
    const std::array<double, 2> u = {2.706 + x, 3.206 + x * 1e-9};
    const std::array<double, 1> dy = {std::exp(x) * 1e5};
    const RunState state = k < 40 ? RunState::running : RunState::returning;
    ASSERT_EQ(w.write_row(Row{static_cast<double>(k), k, du, u, dy, 0, state}), WriteStatus::ok);
    written.push_back(x);
  }
  std::fclose(f);
  const ReadResult r = read_run_log(path);
  std::remove(path);
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  ASSERT_EQ(r.log.rows(), 50U);
  for (std::size_t k = 0; k < 50; ++k) {
    EXPECT_EQ(r.log.du[0][k], written[k]);
    EXPECT_EQ(r.log.du[1][k], written[k] * 1e-9);
    EXPECT_EQ(r.log.u[0][k], 2.706 + written[k]);
    EXPECT_EQ(r.log.dy[0][k], std::exp(written[k]) * 1e5);
  }
  EXPECT_EQ(r.log.format_version, 3);
  ASSERT_EQ(r.log.segment.size(), 50U);
  EXPECT_EQ(r.log.segment[49], 0U);
  ASSERT_EQ(r.log.state.size(), 50U);
  EXPECT_EQ(r.log.state[39], RunState::running);
  EXPECT_EQ(r.log.state[40], RunState::returning);
  EXPECT_EQ(r.log.input_units[1], "kmol/min");
  EXPECT_EQ(r.log.output_names[0], "xD");
}

TEST(RunLogWriter, FormattingAndWritingDoNotAllocate) {
  std::array<char, 1024> buf{};
  const std::array<double, 2> du = {0.1, -0.25};
  const std::array<double, 1> dy = {1.0 / 3.0};
  std::FILE* sink = std::fopen("/dev/null", "wb");
  ASSERT_NE(sink, nullptr);
  FileWriter w(sink, two_by_one(), buf);
  const long before = g_allocations.load();
  EXPECT_EQ(format_header(two_by_one(), buf).status, WriteStatus::ok);
  for (std::uint64_t k = 0; k < 100; ++k) {
    EXPECT_EQ(
        format_row(two_by_one(),
                   Row{static_cast<double>(k), k, du, du, dy, kSkipped, RunState::suspended}, buf)
            .status,
        WriteStatus::ok);
    EXPECT_EQ(w.write_row(Row{static_cast<double>(k), k, du, du, dy, 0}), WriteStatus::ok);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  std::fclose(sink);
  // The counter does count: a vector allocates.
  const long probe = g_allocations.load();
  const std::vector<double> v(1000, 1.0);
  EXPECT_GT(g_allocations.load() - probe, 0) << v[999];
}

}  // namespace
}  // namespace excite::runlog
