// SPDX-License-Identifier: MIT
#pragma once
// The marker of a folder `excite` wrote (issue 40 §3): DIR/.excite-output, its first line
// `excite output v1 KIND` (KIND: "campaign", "montecarlo merge", …), then every file and
// folder the tool wrote there, one path relative to DIR a line (folders end in '/'),
// sorted. A later run of the same kind replaces only what the marker lists: a folder that
// holds anything else (a file the user added, a link planted in it) is not the tool's
// output, whatever its JSON files look like.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace excite::host {

inline constexpr const char* kFolderMarker = ".excite-output";

/// Every entry under `dir`, relative, folders with a trailing '/', sorted; links are
/// entries, never followed; the marker itself left out.
std::vector<std::string> folder_entries(const std::filesystem::path& dir);

/// Writes DIR/.excite-output (whole: host/output/whole_file.hpp) listing `entries`.
void write_folder_marker(const std::filesystem::path& dir, std::string_view kind,
                         const std::vector<std::string>& entries);

/// The entries DIR's marker of `kind` lists; nothing when DIR has no such marker (absent,
/// of another kind, a link, not a regular file, or over 16 MiB).
std::optional<std::vector<std::string>> marked_entries(const std::filesystem::path& dir,
                                                       std::string_view kind);

/// Empty when every entry under `dir` is listed by its marker of `kind`; otherwise why the
/// folder is not only the tool's, for a message: "no .excite-output of an excite KIND" or
/// "NAME is not a file excite wrote".
std::string foreign_entry(const std::filesystem::path& dir, std::string_view kind);

}  // namespace excite::host
