// SPDX-License-Identifier: MIT
#pragma once
// An output folder written whole (host/README.md, "Output files"): everything goes into a
// temporary sibling folder `.NAME.XXXXXX`, and commit() puts it in the folder's place in one
// rename (renameat2 RENAME_EXCHANGE when a previous folder is there, which is then removed).
// An interrupted, failed or size-limited run leaves the previous folder as it was; a run that
// throws also removes its temporary folder (one killed by a signal leaves it behind, hidden).
//
// Before any work the constructor checks the name: it must be a folder or not exist yet (a
// symbolic link is followed to its target); a non-empty folder is refused unless it is a
// previous output of the same `kind` holding nothing but what that run wrote (its marker,
// folder_marker.hpp, lists every entry) or `overwrite` is set — then the whole folder,
// anything else in it included, is replaced. commit() writes the marker of `kind` listing
// everything in the new folder. Errors are std::runtime_error "PATH: cannot be written
// (REASON)".

#include <filesystem>
#include <string>

namespace excite::host {

class WholeFolder {
 public:
  /// `kind` names the tool's output in the marker and in messages ("campaign").
  WholeFolder(const std::filesystem::path& path, bool overwrite, std::string kind);
  WholeFolder(const WholeFolder&) = delete;
  WholeFolder& operator=(const WholeFolder&) = delete;
  /// Not committed: the temporary folder is removed, the folder is untouched.
  ~WholeFolder();

  /// Where to write (the temporary folder until commit()).
  const std::filesystem::path& staging() const { return staging_; }

  /// Writes the marker, puts the temporary folder in the folder's place; the previous one
  /// is removed.
  void commit();

 private:
  std::filesystem::path path_;     // as given
  std::filesystem::path target_;   // the symlinks' final target
  std::filesystem::path staging_;  // empty after commit
  std::string kind_;
};

}  // namespace excite::host
