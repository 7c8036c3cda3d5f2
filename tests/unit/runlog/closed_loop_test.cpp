// SPDX-License-Identifier: MIT
// Run-log v4 (firmware/runlog/README.md, "Version 4"): a closed-loop run's header keys and
// columns written, read back to the identical values, and the open-loop log unchanged (v3).
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <new>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"
#include "firmware/runlog/writer.hpp"

// Every operator new of this program is counted: formatting a v4 row allocates nothing
// (the gateway's log thread formats rows after start-up; STYLE.md practice 5).
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
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
#pragma GCC diagnostic pop

namespace excite::runlog {
namespace {

constexpr std::array<Channel, 2> kInputs = {{{"R", "lb/min"}, {"S", "lb/min"}}};
constexpr std::array<Channel, 2> kOutputs = {{{"xD", "mol%"}, {"xB", "mol%"}}};
constexpr std::array<std::size_t, 2> kBothOutputs = {0, 1};
constexpr std::array<std::size_t, 1> kSecondInput = {1};

Header closed_header(Excitation excitation, std::span<const std::size_t> r_channels) {
  Header h{"woodberry2x2", "sp.plan", 1.0, kInputs, kOutputs, "excite simulate 0.1.0"};
  h.closed_loop = {true, excitation, "pi examples/woodberry2x2.pi.toml", r_channels};
  return h;
}

std::string write_log(const Header& h, int rows, std::size_t r_count) {
  std::vector<char> buf(1 << 14);
  std::string text;
  const WriteResult head = format_header(h, buf);
  EXPECT_EQ(head.status, WriteStatus::ok) << head.message;
  text.append(buf.data(), head.length);
  for (int k = 0; k < rows; ++k) {
    const double x = 0.1 * k;
    const std::array<double, 2> du{x, -x}, u{1.0 + x, 2.0 - x}, dy{0.5 * x, -0.25 * x};
    const std::array<double, 2> r{0.3 + x, -0.3};
    const std::array<double, 2> uc{x - 0.01, -x}, ysp{0.3 + x, -0.3};
    const std::array<MvState, 2> st{MvState::ok, k == 1 ? MvState::clamped_high : MvState::ok};
    Row row{
        static_cast<double>(k), static_cast<std::uint64_t>(k), du, u, dy, 0, RunState::running, 0};
    row.r = std::span<const double>(r.data(), r_count);
    row.uc = uc;
    row.ysp = ysp;
    row.st = st;
    row.mode = k == 2 ? LoopMode::suspended : LoopMode::test;
    std::vector<char> line(max_closed_loop_row_chars(2, 2, r_count));
    const WriteResult w = format_row(h, row, line);
    EXPECT_EQ(w.status, WriteStatus::ok) << w.message;
    text.append(line.data(), w.length);
  }
  return text;
}

TEST(RunLogV4, SetpointRunWritesTheAgreedHeaderAndColumnOrder) {
  const std::string text = write_log(closed_header(Excitation::setpoint, kBothOutputs), 1, 2);
  EXPECT_EQ(text.substr(0, text.find('\n')), "# excite run log v4");
  EXPECT_NE(text.find("\n# loop: closed\n# excitation: setpoint\n# controller: pi "
                      "examples/woodberry2x2.pi.toml\n"),
            std::string::npos);
  EXPECT_NE(text.find("\nt_min,k,du_R,du_S,u_R,u_S,dy_xD,dy_xB,r_xD,r_xB,uc_R,uc_S,ysp_xD,"
                      "ysp_xB,st_R,st_S,mode,flags,state,segment\n"),
            std::string::npos);
}

TEST(RunLogV4, ReadsBackEveryClosedLoopColumn) {
  const std::string text = write_log(closed_header(Excitation::setpoint, kBothOutputs), 3, 2);
  const ReadResult r = parse_run_log(text, "cl.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  const ClosedLoopLog& cl = r.log.closed_loop;
  EXPECT_EQ(r.log.format_version, 4);
  ASSERT_TRUE(cl.closed);
  EXPECT_EQ(cl.excitation, Excitation::setpoint);
  EXPECT_EQ(cl.controller, "pi examples/woodberry2x2.pi.toml");
  EXPECT_EQ(cl.r_channels, (std::vector<std::size_t>{0, 1}));
  ASSERT_EQ(cl.r.size(), 2U);
  EXPECT_EQ(cl.r[0], (std::vector<double>{0.3, 0.4, 0.5}));  // round trip: identical doubles
  EXPECT_EQ(cl.uc[0][2], 0.2 - 0.01);
  EXPECT_EQ(cl.ysp[1], (std::vector<double>{-0.3, -0.3, -0.3}));
  EXPECT_EQ(cl.st[1][1], MvState::clamped_high);
  EXPECT_EQ(cl.mode, (std::vector<LoopMode>{LoopMode::test, LoopMode::test, LoopMode::suspended}));
  EXPECT_EQ(r.log.du[0][2], 0.2);  // u and y keep their v3 meaning
}

TEST(RunLogV4, MvDitherOnOneInputHasOneRColumn) {
  const std::string text = write_log(closed_header(Excitation::mv, kSecondInput), 2, 1);
  EXPECT_NE(text.find(",dy_xB,r_S,uc_R,"), std::string::npos);
  const ReadResult r = parse_run_log(text, "cl.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_EQ(r.log.closed_loop.excitation, Excitation::mv);
  EXPECT_EQ(r.log.closed_loop.r_channels, (std::vector<std::size_t>{1}));
  EXPECT_EQ(r.log.closed_loop.r[0], (std::vector<double>{0.3, 0.4}));
}

TEST(RunLogV4, OpenLoopLogStaysV3WithNoClosedLoopColumns) {
  Header h{"woodberry2x2", "sp.plan", 1.0, kInputs, kOutputs};
  std::vector<char> buf(4096);
  const WriteResult head = format_header(h, buf);
  const std::string text(buf.data(), head.length);
  EXPECT_EQ(text.substr(0, text.find('\n')), "# excite run log v3");
  EXPECT_EQ(text.find("loop"), std::string::npos);
  EXPECT_EQ(text.find("mode"), std::string::npos);
}

TEST(RunLogV4, V3LogReadsWithAnEmptyClosedLoop) {
  const std::string text =
      "# excite run log v3\n# plant: p\n# plan: q\n# sample_time_min: 1\n# inputs: R\n"
      "# outputs: xD\n# units: R=- xD=-\nt_min,k,du_R,u_R,dy_xD,flags,state,segment\n"
      "0,0,0,0,0,0,running,0\n1,1,0,0,0,0,running,0\n";
  const ReadResult r = parse_run_log(text, "open.csv");
  ASSERT_TRUE(r.ok()) << r.error->to_string();
  EXPECT_FALSE(r.log.closed_loop.closed);
  EXPECT_TRUE(r.log.closed_loop.r.empty());
  EXPECT_TRUE(r.log.closed_loop.mode.empty());
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

TEST(RunLogV4, RefusesAMissingKeyAnUnknownModeAndABadStatusByName) {
  const std::string good = write_log(closed_header(Excitation::setpoint, kBothOutputs), 2, 2);
  const auto error_of = [](const std::string& text) {
    const ReadResult r = parse_run_log(text, "cl.csv");
    return r.ok() ? std::string("accepted") : r.error->to_string();
  };
  EXPECT_NE(error_of(replaced(good, "# excitation: setpoint\n", "")).find("no '# excitation:'"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, "# excitation: setpoint", "# excitation: dither"))
                .find("excitation = 'dither', expected setpoint, mv or both"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, ",test,0,running", ",auto,0,running"))
                .find("mode = 'auto', expected a loop mode"),
            std::string::npos);
  EXPECT_NE(error_of(replaced(good, ",0,0,test,", ",0,7,test,")).find("st_S = '7', expected an MV"),
            std::string::npos);
  // r columns only on the excitation's side: r_R in a setpoint log is no column of it.
  EXPECT_NE(error_of(replaced(good, ",r_xD,", ",r_R,")).find("unexpected column 'r_R'"),
            std::string::npos);
}

TEST(RunLogV4, FormattingAClosedLoopRowAllocatesNothing) {
  const Header h = closed_header(Excitation::mv, kSecondInput);
  std::array<char, max_closed_loop_row_chars(2, 2, 1)> line{};
  const std::array<double, 2> two{0.125, -3.5e-7};
  const std::array<double, 1> one{0.25};
  const std::array<MvState, 2> st{MvState::windup, MvState::manual};
  Row row{1.0, 1, two, two, two, 4, RunState::running, 0};
  row.r = one;
  row.uc = two;
  row.ysp = two;
  row.st = st;
  row.mode = LoopMode::control;
  const long before = g_allocations.load();
  const WriteResult w = format_row(h, row, line);
  EXPECT_EQ(g_allocations.load(), before);
  ASSERT_EQ(w.status, WriteStatus::ok) << w.message;
  EXPECT_NE(
      std::string(line.data(), w.length).find(",0.25,0.125,-3.5e-07,0.125,-3.5e-07,3,4,control,4,"),
      std::string::npos)
      << std::string(line.data(), w.length);
}

TEST(RunLogV4, WriterRefusesRowsOfTheWrongWidthAndAHeaderWithoutR) {
  const Header h = closed_header(Excitation::setpoint, kBothOutputs);
  std::vector<char> buf(4096);
  const std::array<double, 2> two{0.0, 0.0};
  const std::array<MvState, 2> st{};
  Row row{0.0, 0, two, two, two, 0, RunState::running, 0};
  row.r = std::span<const double>(two.data(), 1);  // one r value for two r channels
  row.uc = two;
  row.ysp = two;
  row.st = st;
  EXPECT_EQ(format_row(h, row, buf).status, WriteStatus::bad_argument);
  Header none = closed_header(Excitation::setpoint, {});
  EXPECT_EQ(format_header(none, buf).status, WriteStatus::invalid_field);
}

// `# excitation: both` (r on the CV setpoints and on the MVs): the outputs' r columns first,
// then the inputs', in one channel index space (outputs 0 … p − 1, then p + input index).
TEST(RunLogV4, BothWritesTheOutputsRColumnsThenTheInputsAndReadsThemBack) {
  constexpr std::array<std::size_t, 3> kChannels = {0, 1, 3};  // xD, xB, then S
  const Header h = closed_header(Excitation::both, kChannels);
  std::vector<char> buf(1 << 14);
  const WriteResult head = format_header(h, buf);
  ASSERT_EQ(head.status, WriteStatus::ok) << head.message;
  std::string text(buf.data(), head.length);
  EXPECT_NE(text.find("\n# excitation: both\n"), std::string::npos) << text;
  EXPECT_NE(text.find(",dy_xB,r_xD,r_xB,r_S,uc_R,"), std::string::npos) << text;
  const std::array<double, 2> du{0.1, -0.1}, u{1.1, 1.9}, dy{0.05, -0.02};
  const std::array<double, 3> r{0.25, -0.5, 0.125};
  const std::array<double, 2> uc{0.09, -0.1}, ysp{0.25, -0.5};
  const std::array<MvState, 2> st{MvState::ok, MvState::windup};
  Row row{1.0, 1, du, u, dy, 0, RunState::running, 0};
  row.r = r;
  row.uc = uc;
  row.ysp = ysp;
  row.st = st;
  for (int k = 1; k <= 2; ++k) {  // two rows: the reader wants at least two
    row.k = static_cast<std::uint64_t>(k);
    row.t_min = static_cast<double>(k);
    const WriteResult w = format_row(h, row, buf);
    ASSERT_EQ(w.status, WriteStatus::ok) << w.message;
    text.append(buf.data(), w.length);
  }
  const ReadResult back = parse_run_log(text, "both.csv");
  ASSERT_TRUE(back.ok()) << back.error->to_string();
  const ClosedLoopLog& cl = back.log.closed_loop;
  EXPECT_EQ(cl.excitation, Excitation::both);
  EXPECT_EQ(cl.r_channels, (std::vector<std::size_t>{0, 1, 3}));
  ASSERT_EQ(cl.r.size(), 3U);
  EXPECT_EQ(cl.r[0][0], 0.25);
  EXPECT_EQ(cl.r[1][0], -0.5);
  EXPECT_EQ(cl.r[2][0], 0.125) << "r_S: the second input, index p + 1";
  EXPECT_EQ(cl.st[1][0], MvState::windup);

  constexpr std::array<std::size_t, 1> kBeyond = {4};  // p + n = 4 channels: 0 … 3
  EXPECT_EQ(format_header(closed_header(Excitation::both, kBeyond), buf).status,
            WriteStatus::invalid_field);
}

}  // namespace
}  // namespace excite::runlog
