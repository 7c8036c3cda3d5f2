// SPDX-License-Identifier: MIT
#pragma once
// Running the report's gnuplot scripts (gnuplot is the project's plotting tool).

#include <filesystem>
#include <string>

namespace excite::host {

/// 'it''s' — a gnuplot single-quoted string.
std::string gnuplot_string(const std::string& text);

/// Runs every *.gp in `folder`, `threads` at a time. Throws std::runtime_error with
/// gnuplot's output when one fails.
void run_gnuplot_scripts(const std::filesystem::path& folder, int threads);

}  // namespace excite::host
