// SPDX-License-Identifier: MIT
// What the loop's tests (hil/loop, hil/gateway) share beside their fixture: the plant they
// run, the limits loop-config gives it, and small readers of files and logs. One definition
// each (the test executables compile their sources in unity batches, tests/CMakeLists.txt).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "firmware/runlog/reader.hpp"

namespace excite::test {

// The case study most loop tests stream: Wood–Berry, T = 1 min.
inline constexpr const char* kPlant = "woodberry2x2";
// loop-config --input-range: limits baseline ± 2.
inline constexpr double kInputRange = 2.0;
// The watchdog's trip counter: the control block's register +6.
inline constexpr int kWatchdogTrips = 406;
// A disk that fills: the gateway run under `prlimit --fsize` (ulimit -f 20).
inline constexpr const char* kPrlimit = "/usr/bin/prlimit";
inline constexpr long kSizeLimit = 20 * 1024;
// A single-precision register's relative resolution.
inline constexpr double kFloat32Epsilon = 0x1p-24;

#ifdef EXCITE_CONTROL_EXAMPLES
// The Wood–Berry PI controller file of sim/control/examples.
inline const std::string kPi = std::string(EXCITE_CONTROL_EXAMPLES) + "/woodberry2x2.pi.toml";
#endif

// The whole file as text ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The whole file as bytes (none when it cannot be read).
inline std::vector<std::uint8_t> bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// How often `what` occurs in `text`, overlaps counted.
inline std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

inline double max_abs(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// The rows of a run log with `flag` set.
inline std::size_t rows_with(const runlog::RunLog& log, std::uint32_t flag) {
  return static_cast<std::size_t>(std::count_if(
      log.flags.begin(), log.flags.end(), [flag](std::uint32_t f) { return (f & flag) != 0; }));
}

}  // namespace excite::test
