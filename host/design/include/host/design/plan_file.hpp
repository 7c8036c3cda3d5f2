// SPDX-License-Identifier: MIT
#pragma once
// Plan files on disk, host side: the bytes are the firmware's (firmware/plan/README.md).

#include <filesystem>
#include <memory>

#include "firmware/plan/plan.hpp"

namespace excite::host {

/// Encodes and writes `plan` to `path` whole or not at all (host/output/whole_file.hpp). Throws
/// std::runtime_error naming the path.
void write_plan_file(const plan::Plan& plan, const std::filesystem::path& path);

/// Reads and decodes `path`. Throws std::invalid_argument "<path>: <why>" for a missing,
/// truncated, corrupted or newer-version file: never a garbage plan.
std::unique_ptr<plan::Plan> read_plan_file(const std::filesystem::path& path);

}  // namespace excite::host
