// SPDX-License-Identifier: MIT
#pragma once
// The segment inbox's files (issue 39 §3; README "Plan segments", inbox rules): the folder
// and every name in it are input from outside the gateway, so
//  - the folder must be a folder (not a link) owned by the gateway's user and writable by
//    nobody else — otherwise another user could drop a plan, or plant a link;
//  - next.plan is opened without following a link and without blocking (O_NOFOLLOW |
//    O_NONBLOCK: a FIFO swapped in cannot hold the inbox thread), and read only when it is a
//    regular file owned by the gateway's user and no larger than the largest plan; the bytes
//    read are what the gateway checks and keeps;
//  - a file is moved aside, kept or refused, only under a name nobody holds
//    (renameat2 RENAME_NOREPLACE): a kept segment or an earlier refusal is never overwritten.
// Start-up and the inbox thread only (they allocate); not the cyclic path.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace excite::app {

/// "" when `dir` is a folder (not a symbolic link) owned by this process's effective user and
/// not writable by group or others; else "--segment-inbox = DIR (…), expected …".
std::string check_inbox_folder(const std::string& dir);

struct SegmentFile {
  bool present = false;             // something is named `path` (a file, link, FIFO, …)
  std::vector<std::uint8_t> bytes;  // the file's bytes, when refusal is empty
  std::string refusal;              // why it is not read ("FIELD = VALUE, expected …"), or ""
};

/// Reads `path` as a plan segment may be read: no link followed, no blocking open, a regular
/// file owned by this process's effective user, at most `max_bytes`.
SegmentFile read_segment_file(const std::string& path, std::size_t max_bytes);

/// Renames `from` to DIR/STEM + EXT, or DIR/STEM-2 + EXT, -3, … (the first name nobody holds;
/// never over an existing file). The new name (its file name only), or "" with `error` set.
std::string rename_aside(const std::string& from, const std::string& dir, const std::string& stem,
                         const std::string& ext, std::string& error);

}  // namespace excite::app
