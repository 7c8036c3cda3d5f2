// SPDX-License-Identifier: MIT
#pragma once
// A run log that its producer (the gateway's log thread) is still writing, read by the host
// while the test runs: only whole lines are parsed, and the rows of one plan segment are found
// by the log's `segment` and `state` columns (firmware/runlog/README.md, v3).

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "firmware/runlog/reader.hpp"

namespace excite::host {

/// The log at `path` up to its last complete line (a row being written is not read), or
/// nullopt while the file is missing or its header and column row are not complete yet.
/// Throws std::runtime_error with the reader's message ("FILE:LINE: column C: …") when the
/// complete part is not a valid run log.
std::optional<runlog::RunLog> read_growing_log(const std::filesystem::path& path);

/// A table row of segment `id`: a row of that segment written in state running and not
/// flagged suspended (a row holding the baseline while the gateway awaited a segment, or
/// while suspended, is not one).
bool is_table_row(const runlog::RunLog& log, std::size_t row, std::uint32_t id);

/// Where segment `id`'s `rows` table rows end in `log`, searching from row `from`.
struct SegmentSpan {
  bool complete = false;  // all `rows` table rows are in the log …
  std::size_t end = 0;    // … and the last is row end − 1 (valid when complete)
  std::size_t found = 0;  // table rows of the segment found so far
  std::string ended;      // not complete and never will be: why, naming the row ("" else)
};

/// The span [from, end) holds every row from `from` on up to segment `id`'s last table row:
/// rows still of the segment before (the baseline held while the gateway awaited `id`, in
/// real time) and suspended rows in between included, so the record stays contiguous.
/// `ended` is set when the run has left the running states (completed, aborted, returning,
/// safe, …) or a later segment id appears before the `rows` table rows were found.
SegmentSpan find_segment(const runlog::RunLog& log, std::uint32_t id, std::size_t from,
                         std::uint32_t rows);

}  // namespace excite::host
