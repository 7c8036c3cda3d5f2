// SPDX-License-Identifier: MIT
#pragma once
// The plan file: binary, little-endian, versioned, CRC-32 checked (README.md, byte by
// byte). Only the used sources, segments, lines, channels and mix entries are written.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

#include "firmware/plan/plan.hpp"

namespace excite::plan {

/// File magic, bytes 0–7.
inline constexpr std::array<std::uint8_t, 8> kMagic = {0x89, 'E', 'X', 'P', 'L', 'A', 'N', '\n'};
inline constexpr std::size_t kHeaderSize = 16;  // magic, version, flags, payload length
inline constexpr std::size_t kTrailerSize = 4;  // CRC-32

/// Bytes encode() writes for `plan` (its recipe's counts must be within capacity).
std::size_t encoded_size(const Plan& plan);

/// Upper bound of encoded_size() over all plans: a buffer this large always suffices.
std::size_t max_encoded_size();

struct [[nodiscard]] EncodeResult {
  Status status;         // ok, or why nothing was written
  std::size_t size = 0;  // bytes written to the front of `out` when ok, else 0
};

/// Writes `plan` as a version-kFormatVersion (3) file into the front of `out`, or as a
/// version-4 file when meta.excitation is not open_loop.
/// Refuses (nothing written) an invalid plan (validate(plan)) and an `out` shorter than
/// encoded_size(plan) (capacity_exceeded). The same plan always gives the same bytes.
EncodeResult encode(const Plan& plan, std::span<std::uint8_t> out);

/// Reads a plan file that must fill `in` exactly. On success `out` holds the plan with
/// meta.format_version set to the file's version. Refuses, with a message naming what
/// was found and expected: truncated input, bytes after the end, bad magic, a format
/// version this build does not read (newer or 0), nonzero reserved flags, checksum
/// mismatch, counts beyond capacity, unknown source kinds, text without room or with a
/// NUL, and any plan that fails validate(). On error `out` is a default Plan.
/// A closed-loop plan (version 4: setpoint or mv excitation) is refused unless
/// `closed_loop_allowed`: a reader that streams the table as MV moves (the gateway, the plant
/// server's --plan) must not take setpoint offsets for moves.
Status decode(std::span<const std::uint8_t> in, Plan& out, bool closed_loop_allowed = false);

}  // namespace excite::plan
