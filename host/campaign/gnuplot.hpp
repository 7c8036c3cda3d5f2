// SPDX-License-Identifier: MIT
#pragma once
// Running the report's gnuplot scripts (gnuplot is the project's plotting tool). Only the
// scripts this run wrote are run, each by its name, and gnuplot is started with an argument
// vector in the figures folder (host/process), never through a shell: a folder name with
// quotes or `;` is only a name, and a *.gp someone else put into the folder is never run.
// The scripts name their data and SVG files relative to the figures folder, as gnuplot
// single-quoted strings (gnuplot_string), so the output folder's name never enters them.

#include <filesystem>
#include <string>
#include <vector>

namespace excite::host {

/// 'it''s' — a gnuplot single-quoted string (no backquote, macro or backslash is expanded
/// inside one). Throws std::invalid_argument for a control character (a newline would end
/// the gnuplot command and start another).
std::string gnuplot_string(const std::string& text);

/// Runs gnuplot on each of `scripts` (file names in `folder`), `threads` at a time, in
/// `folder`. Throws std::runtime_error with gnuplot's output when one fails (also when a
/// signal, e.g. SIGXFSZ under `ulimit -f`, ended it), or when an SVG it was to draw
/// (`set output '…svg'`) is missing or cut short (no closing </svg>).
void run_gnuplot_scripts(const std::filesystem::path& folder,
                         const std::vector<std::string>& scripts, int threads);

}  // namespace excite::host
