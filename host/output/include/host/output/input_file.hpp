// SPDX-License-Identifier: MIT
#pragma once
// An input file read whole, with a size bound (issue 40 §2, §5): what the name names after
// its links must be a regular file of at most `max_bytes`. It is opened without blocking and
// checked on the open descriptor, so a FIFO is refused, never waited on, and /dev/zero or a
// file that grows while read is refused at the bound instead of filling the memory.

#include <cstdint>
#include <filesystem>
#include <string>

namespace excite::host {

/// The bytes of `path`. Throws std::invalid_argument in the one message form, naming the
/// file and `what` it should be: "PATH: size = N bytes, expected at most M bytes (WHAT)",
/// "PATH: file type = FIFO, expected a regular file (WHAT)", "PATH: cannot be read
/// (REASON), expected WHAT".
std::string read_input_file(const std::filesystem::path& path, std::uintmax_t max_bytes,
                            const std::string& what);

}  // namespace excite::host
