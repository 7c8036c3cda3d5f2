// SPDX-License-Identifier: MIT
#pragma once
// Every output file of `excite` goes through here, so each is written whole or not at all
// and nothing the user did not name is replaced (host/README.md, "Output files"):
//   - "-": standard output, written through;
//   - a name of one of this process's descriptors, or a link to one (/dev/stdout,
//     /dev/stderr, /dev/fd/N, /proc/self/fd/N): written through that descriptor, as the
//     shell opened it (`>> journal.log` appends, a pipe or a socket works);
//   - what stat() of the name as given says (through any links) is an existing character
//     or block device, FIFO or socket: written through, never replaced (/dev/null, a FIFO);
//     a write error is an error;
//   - a symbolic link to a regular file or to nothing: followed (up to 40 links); its final
//     target gets the rules below, the link itself stays;
//   - a directory: refused;
//   - a regular file, or a name that does not exist yet: written to a temporary file
//     `.NAME.XXXXXX` in the same folder, flushed and fsync'ed, then renamed over the name.
//     A replaced file keeps its permission bits; a new one gets 0666 & ~umask. On any
//     failure (full disk, `ulimit -f`, an exception while writing) the temporary file is
//     removed and the old file, if any, is untouched.
// Errors are std::runtime_error "PATH: cannot be written (REASON)". SIGXFSZ is ignored
// process-wide from the first use, so a file-size limit is a write error, not a kill that
// would leave the temporary file behind.

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace excite::host {

class WholeFile {
 public:
  /// Opens the temporary file (or the device, or standard output) for `path`.
  explicit WholeFile(const std::filesystem::path& path);
  WholeFile(const WholeFile&) = delete;
  WholeFile& operator=(const WholeFile&) = delete;
  /// Not committed: the temporary file is removed, the target is untouched.
  ~WholeFile();

  /// Where to write; owned by this object.
  std::FILE* stream() { return stream_; }
  /// The name the user gave (what error messages show).
  const std::filesystem::path& path() const { return path_; }

  /// Writes `bytes` and flushes them; throws (and discards the temporary file) on an error.
  void write(std::string_view bytes);

  /// Flushes, syncs and renames the temporary file over the target (or flushes the device).
  /// Throws on any write error; afterwards the object holds nothing.
  void commit();

 private:
  [[noreturn]] void fail(const std::string& reason);
  void discard() noexcept;

  std::filesystem::path path_;       // as given
  std::filesystem::path target_;     // the symlinks' final target
  std::filesystem::path temporary_;  // empty when written through
  std::FILE* stream_ = nullptr;
  bool is_stdout_ = false;
};

/// Whether writing `path` writes this process's standard output ("-", /dev/stdout, or the
/// very file standard output is: same device and inode). Commands then print their human
/// text on stderr.
bool writes_to_stdout(const std::filesystem::path& path);

/// Writes `bytes` to `path` whole or not at all (the rules above).
void write_whole_file(const std::filesystem::path& path, std::string_view bytes);

}  // namespace excite::host
