// SPDX-License-Identifier: MIT
#pragma once
// Plain-text tables for the terminal: columns right-aligned to their widest cell.

#include <ostream>
#include <string>
#include <vector>

namespace excite::host {

class TextTable {
 public:
  explicit TextTable(std::vector<std::string> header) : rows_{std::move(header)} {}
  void add_row(std::vector<std::string> row) { rows_.push_back(std::move(row)); }
  void print(std::ostream& out) const;

 private:
  std::vector<std::vector<std::string>> rows_;
};

/// A number with `digits` significant digits ("%.*g"); "-" for NaN.
std::string num(double value, int digits = 4);

}  // namespace excite::host
