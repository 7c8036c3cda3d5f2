// SPDX-License-Identifier: MIT
// Fuzzes the run-log reader (firmware/runlog, runlog::parse_run_log), which every host tool
// and the gateway's log checks use. Properties: a rejected log carries a message and a
// printable location; an accepted log is rectangular (every column has rows() values, one
// du, u per input and one dy per output, names and units per channel), has at least
// min_rows rows, a finite positive sample time, finite numbers, known flags and consecutive
// sample indices (a row flagged skipped jumps by the ticks missed); and it survives the writer:
// format_header + format_row of what was read, read again, gives the identical columns (the
// writer's shortest round-trip numbers).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "check.hpp"
#include "firmware/runlog/format.hpp"
#include "firmware/runlog/reader.hpp"
#include "firmware/runlog/writer.hpp"

namespace {

using excite::runlog::Channel;
using excite::runlog::RunLog;

std::vector<Channel> channels(const std::vector<std::string>& names,
                              const std::vector<std::string>& units) {
  std::vector<Channel> out;
  for (std::size_t i = 0; i < names.size(); ++i) out.push_back({names[i], units[i]});
  return out;
}

std::vector<double> row_of(const std::vector<std::vector<double>>& columns, std::size_t r) {
  std::vector<double> out;
  for (const auto& column : columns) out.push_back(column[r]);
  return out;
}

// Writes `log` with the writer and reads it back: the same header and identical columns.
void check_rewrite(const RunLog& log) {
  const auto inputs = channels(log.input_names, log.input_units);
  const auto outputs = channels(log.output_names, log.output_units);
  const excite::runlog::Header header{log.plant, log.plan, log.sample_time_min,
                                      inputs,    outputs,  log.producer};
  // Room for the header: every name appears four times (list, units, column row), with
  // prefixes and separators.
  std::size_t room = 4096 + log.plant.size() + log.plan.size() + log.producer.size();
  for (const auto* names :
       {&log.input_names, &log.output_names, &log.input_units, &log.output_units}) {
    for (const auto& name : *names) room += 8 * (name.size() + 8);
  }
  std::string text(room, '\0');
  auto written = excite::runlog::format_header(header, text);
  EXCITE_FUZZ_CHECK(written.status == excite::runlog::WriteStatus::ok,
                    "the writer refuses a header the reader accepted");
  text.resize(written.length);
  std::vector<char> line(excite::runlog::max_row_chars(inputs.size(), outputs.size()));
  for (std::size_t r = 0; r < log.rows(); ++r) {
    const auto du = row_of(log.du, r);
    const auto u = row_of(log.u, r);
    const auto dy = row_of(log.dy, r);
    const excite::runlog::Row row{log.t_min[r], log.k[r], du, u, dy, log.flags[r]};
    written = excite::runlog::format_row(header, row, line);
    EXCITE_FUZZ_CHECK(written.status == excite::runlog::WriteStatus::ok,
                      "the writer refuses a row the reader accepted");
    text.append(line.data(), written.length);
  }
  const auto again = excite::runlog::parse_run_log(text, "rewritten.csv");
  EXCITE_FUZZ_CHECK(again.ok(), "the reader refuses what the writer wrote");
  const RunLog& back = again.log;
  EXCITE_FUZZ_CHECK(back.input_names == log.input_names && back.output_names == log.output_names &&
                        back.input_units == log.input_units &&
                        back.output_units == log.output_units,
                    "channels changed in a write/read round trip");
  EXCITE_FUZZ_CHECK(back.sample_time_min == log.sample_time_min && back.t_min == log.t_min &&
                        back.k == log.k && back.flags == log.flags && back.du == log.du &&
                        back.u == log.u && back.dy == log.dy,
                    "numbers changed in a write/read round trip");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const excite::runlog::ReadOptions options;
  const excite::runlog::ReadResult result =
      excite::runlog::parse_run_log(text, "fuzz.csv", options);
  if (!result.ok()) {
    EXCITE_FUZZ_CHECK(!result.error->message.empty(), "a rejection names its reason");
    EXCITE_FUZZ_CHECK(!result.error->to_string().empty(), "a rejection prints");
    return 0;
  }
  const excite::runlog::RunLog& log = result.log;
  const std::size_t rows = log.rows();
  const std::size_t inputs = log.input_names.size();
  const std::size_t outputs = log.output_names.size();
  EXCITE_FUZZ_CHECK(rows >= options.min_rows, "fewer rows than min_rows accepted");
  EXCITE_FUZZ_CHECK(std::isfinite(log.sample_time_min) && log.sample_time_min > 0.0,
                    "sample time not finite and > 0");
  EXCITE_FUZZ_CHECK(log.input_units.size() == inputs && log.output_units.size() == outputs,
                    "one unit per channel");
  EXCITE_FUZZ_CHECK(log.du.size() == inputs && log.u.size() == inputs && log.dy.size() == outputs,
                    "one column per channel");
  EXCITE_FUZZ_CHECK(log.k.size() == rows && log.flags.size() == rows, "k, flags have rows()");
  for (const auto* columns : {&log.du, &log.u, &log.dy}) {
    for (const auto& column : *columns) {
      EXCITE_FUZZ_CHECK(column.size() == rows, "a channel column has rows() values");
    }
  }
  for (std::size_t r = 0; r < rows; ++r) {
    // A row flagged skipped (v2 on) follows ticks the clock missed: k jumps by more than one.
    const bool skipped = log.format_version >= 2 && (log.flags[r] & excite::runlog::kSkipped) != 0U;
    EXCITE_FUZZ_CHECK(
        r == 0 || (skipped ? log.k[r] > log.k[r - 1] + 1 : log.k[r] == log.k[r - 1] + 1),
        "sample indices are consecutive, or jump at a row flagged skipped");
    EXCITE_FUZZ_CHECK(std::isfinite(log.t_min[r]), "time stamps are finite");
    EXCITE_FUZZ_CHECK((log.flags[r] & ~excite::runlog::kKnownFlags) == 0, "only known flags");
  }
  for (const auto* columns : {&log.du, &log.u, &log.dy}) {
    for (const auto& column : *columns) {
      for (const double v : column) EXCITE_FUZZ_CHECK(std::isfinite(v), "values are finite");
    }
  }
  check_rewrite(log);
  return 0;
}
