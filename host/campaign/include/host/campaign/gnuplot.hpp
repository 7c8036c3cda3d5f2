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
#include <string_view>
#include <vector>

namespace excite::host {

/// 'it''s' — a gnuplot single-quoted string (no backquote, macro or backslash is expanded
/// inside one). Throws std::invalid_argument for a control character (a newline would end
/// the gnuplot command and start another).
std::string gnuplot_string(const std::string& text);

/// Runs gnuplot on each of `scripts` (file names in `folder`), `threads` at a time, in
/// `folder`. Throws std::runtime_error with gnuplot's output when one fails (also when a
/// signal, e.g. SIGXFSZ under `ulimit -f`, ended it), or when an SVG it was to draw
/// (`set output '…svg'`) is missing or cut short (no closing </svg>). Each SVG drawn is
/// then compacted in place (svg_compact.hpp). The scripts run in one gnuplot process per
/// thread (gnuplot's start costs more than most figures), `reset` between them.
void run_gnuplot_scripts(const std::filesystem::path& folder,
                         const std::vector<std::string>& scripts, int threads);

/// The figures' sources — the scripts and the data they plot — live in FIGURES/.gnuplot/
/// while the figures are drawn and are removed afterwards: the report links only the SVGs
/// (the data behind them is in the run logs and model files it links). source_name(NAME) is
/// NAME's path relative to the figures folder, as scripts and run_gnuplot_scripts take it.
inline constexpr const char* kFigureSources = ".gnuplot";
std::string source_name(const std::string& file);

/// Writes a figure source (FIGURES/.gnuplot/NAME, from source_name): plainly, without the
/// fsync and rename of host/output — the sources are scratch inside the campaign's temporary
/// folder and are removed once drawn; a missing or short source fails gnuplot, and with it
/// the report. Throws std::runtime_error "PATH: cannot be written (REASON)".
void write_figure_source(const std::filesystem::path& figures, const std::string& name,
                         std::string_view bytes);

/// Creates FIGURES/.gnuplot/ empty (whatever was there goes).
void make_figure_sources(const std::filesystem::path& figures);

/// Removes FIGURES/.gnuplot/ and all it holds.
void remove_figure_sources(const std::filesystem::path& figures);

}  // namespace excite::host
