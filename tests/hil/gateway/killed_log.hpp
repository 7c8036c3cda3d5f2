// SPDX-License-Identifier: MIT
#pragma once
// The run log a SIGKILLed gateway leaves (no flush, no ramp-out), checked beyond "the reader
// accepts it": its last row is whole, and what it says was written is what the peer received.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "firmware/runlog/reader.hpp"

namespace excite::test {

/// The file ends with a newline and its last line has as many fields as the column header
/// (`t_min,…`): no row cut in the middle by the kill. Returns the number of data lines.
inline std::size_t expect_last_row_whole(const std::filesystem::path& csv) {
  std::ifstream in(csv, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  const std::string text = s.str();
  EXPECT_FALSE(text.empty()) << csv;
  if (text.empty()) return 0;
  EXPECT_EQ(text.back(), '\n') << csv << ": the last row is cut";
  std::istringstream lines(text);
  std::size_t header_fields = 0, last_fields = 0, rows = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto fields = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (line.rfind("t_min,", 0) == 0) {
      header_fields = fields;
    } else {
      last_fields = fields;
      ++rows;
    }
  }
  EXPECT_GT(header_fields, 0U) << csv;
  EXPECT_EQ(last_fields, header_fields) << csv << ": the last row has a field missing";
  return rows;
}

/// Every row the gateway logged before it was killed reached the lock-step plant: the plant
/// has a row for each (its row 0 precedes the first write; gateway row r is plant row r + 1,
/// tests/hil/cross) with the same u, to the float32 register's rounding. The plant may have
/// more: writes the gateway made but had not logged yet when it was killed.
inline void expect_logged_rows_reached_the_plant(const runlog::RunLog& gateway,
                                                 const runlog::RunLog& plant) {
  ASSERT_GE(plant.rows(), gateway.rows() + 1) << "rows the gateway logged never reached the plant";
  ASSERT_EQ(plant.u.size(), gateway.u.size());
  std::size_t bad = 0;
  for (std::size_t i = 0; i < gateway.u.size(); ++i) {
    for (std::size_t r = 0; r < gateway.rows(); ++r) {
      const double want = gateway.u[i][r];
      const double got = plant.u[i][r + 1];
      if (std::abs(got - want) > 0x1p-23 * (std::abs(want) + 1.0) && ++bad <= 5) {
        ADD_FAILURE() << gateway.input_names[i] << " row " << r << ": logged " << want
                      << ", the plant received " << got;
      }
    }
  }
  EXPECT_EQ(bad, 0U) << "logged rows that differ from what the plant received";
}

}  // namespace excite::test
