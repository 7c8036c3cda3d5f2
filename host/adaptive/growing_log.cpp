// SPDX-License-Identifier: MIT
#include "host/adaptive/growing_log.hpp"

#include <fstream>
#include <iterator>
#include <stdexcept>

#include "firmware/runlog/format.hpp"
#include "host/identify/run_log_limits.hpp"

namespace excite::host {

namespace {

// Whether the whole lines of `text` reach past the header into the column row (the first
// line that is not a `#` comment).
bool header_complete(const std::string& text) {
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t eol = text.find('\n', at);
    if (eol == std::string::npos) return false;
    if (text[at] != '#') return true;
    at = eol + 1;
  }
  return false;
}

}  // namespace

std::optional<runlog::RunLog> read_growing_log(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t last = text.rfind('\n');
  text.resize(last == std::string::npos ? 0 : last + 1);  // a row being written is not read
  if (!header_complete(text)) return std::nullopt;
  runlog::ReadOptions options = limited_read_options();  // the host's row and value limits
  options.min_rows = 0;
  runlog::ReadResult r = runlog::parse_run_log(text, path.string(), options);
  if (!r.ok()) throw std::runtime_error(r.error->to_string());
  return std::move(r.log);
}

bool is_table_row(const runlog::RunLog& log, std::size_t row, std::uint32_t id) {
  return log.segment[row] == id && log.state[row] == runlog::RunState::running &&
         (log.flags[row] & runlog::kSuspended) == 0U;
}

SegmentSpan find_segment(const runlog::RunLog& log, std::uint32_t id, std::size_t from,
                         std::uint32_t rows) {
  SegmentSpan s;
  for (std::size_t r = from; r < log.rows(); ++r) {
    const runlog::RunState state = log.state[r];
    const bool live = state == runlog::RunState::armed || state == runlog::RunState::running ||
                      state == runlog::RunState::suspended;
    if (!live || log.segment[r] > id) {
      s.ended = "row " + std::to_string(r) + " (k = " + std::to_string(log.k[r]) +
                ") is in state " + std::string(runlog::to_text(state)) + " of segment " +
                std::to_string(log.segment[r]) + " after " + std::to_string(s.found) + " of " +
                std::to_string(rows) + " rows of segment " + std::to_string(id) +
                ", expected the rest of segment " + std::to_string(id) + " running";
      return s;
    }
    if (is_table_row(log, r, id) && ++s.found == rows) {
      s.complete = true;
      s.end = r + 1;
      return s;
    }
  }
  return s;
}

}  // namespace excite::host
