// SPDX-License-Identifier: MIT
#pragma once
// Named entries written into a folder that may hold other things (issue 40 §2): `excite
// montecarlo merge -o OUT` writes OUT/summary.json, OUT/index.html and OUT/figures/ beside
// the shards' folders and the Slurm logs a cluster run keeps in OUT. Only those names are
// the command's; everything else in OUT is kept as it is.
//
// Before any work the constructor checks OUT: a folder or not there yet (a link to a folder
// is followed, as WholeFolder does); each of the names must be absent or listed by OUT's
// marker of the same `kind` (folder_marker.hpp: a previous run's own output), and so must
// everything inside a named folder — else it is refused naming the entry, unless
// `overwrite`. A link planted at a name or inside a named folder is never followed: it is
// not the tool's (refused), and with `overwrite` the link itself is replaced.
//
// Everything is written into a temporary folder OUT/.excite-KIND.XXXXXX; commit() moves each
// entry into place (each one whole: a rename), and rewrites the marker listing what it wrote.
// Not committed: the temporary folder is removed and OUT is untouched. Errors are
// std::runtime_error "PATH: cannot be written (REASON)".

#include <filesystem>
#include <string>
#include <vector>

namespace excite::host {

class OwnEntries {
 public:
  OwnEntries(const std::filesystem::path& folder, bool overwrite, std::string kind,
             std::vector<std::string> names);
  OwnEntries(const OwnEntries&) = delete;
  OwnEntries& operator=(const OwnEntries&) = delete;
  ~OwnEntries();

  /// Where to write the entries (a temporary folder until commit()).
  const std::filesystem::path& staging() const { return staging_; }

  /// Replaces each named entry of the folder by the one written in staging() (a name not
  /// written is left as it was) and rewrites the marker.
  void commit();

 private:
  std::filesystem::path path_;     // as given
  std::filesystem::path target_;   // the folder, links followed
  std::filesystem::path staging_;  // empty after commit
  std::string kind_;
  std::vector<std::string> names_;
};

}  // namespace excite::host
