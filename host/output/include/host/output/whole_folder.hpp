// SPDX-License-Identifier: MIT
#pragma once
// An output folder written whole (host/README.md, "Output files"): everything goes into a
// temporary sibling folder `.NAME.XXXXXX`, and commit() puts it in the folder's place in one
// rename (renameat2 RENAME_EXCHANGE when a previous folder is there, which is then removed).
// An interrupted, failed or size-limited run leaves the previous folder as it was; a run that
// throws also removes its temporary folder (one killed by a signal leaves it behind, hidden).
//
// Before any work the constructor checks the name: it must be a folder or not exist yet (a
// symbolic link is followed to its target); a non-empty folder is refused unless
// `is_previous` says it is a previous output of the same kind or `overwrite` is set — then
// the whole folder, anything else in it included, is replaced. Errors are
// std::runtime_error "PATH: cannot be written (REASON)".

#include <filesystem>
#include <functional>

namespace excite::host {

class WholeFolder {
 public:
  WholeFolder(const std::filesystem::path& path, bool overwrite,
              const std::function<bool(const std::filesystem::path&)>& is_previous,
              const char* what_previous);
  WholeFolder(const WholeFolder&) = delete;
  WholeFolder& operator=(const WholeFolder&) = delete;
  /// Not committed: the temporary folder is removed, the folder is untouched.
  ~WholeFolder();

  /// Where to write (the temporary folder until commit()).
  const std::filesystem::path& staging() const { return staging_; }

  /// Puts the temporary folder in the folder's place; the previous one is removed.
  void commit();

 private:
  std::filesystem::path path_;     // as given
  std::filesystem::path target_;   // the symlinks' final target
  std::filesystem::path staging_;  // empty after commit
};

}  // namespace excite::host
