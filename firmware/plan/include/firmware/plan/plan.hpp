// SPDX-License-Identifier: MIT
#pragma once
// The plan: a recipe (firmware/signal/recipe.hpp) plus what the gateway and the run log
// need to know about it. Written by the host, read by the gateway (README.md gives the
// file format byte by byte). Fixed capacity, no heap.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "firmware/signal/recipe.hpp"
#include "firmware/signal/status.hpp"

namespace excite::plan {

using signal::Status;
using signal::StatusCode;

/// Format version this build writes, and the newest it reads.
inline constexpr std::uint16_t kFormatVersion = 3;
/// A closed-loop plan (Metadata::excitation not open_loop) is written as version 4: version 3
/// plus one byte, the excitation (README, "Version 4"). An open-loop plan stays version 3,
/// byte for byte; this build reads versions 1 … kNewestFormatVersion.
inline constexpr std::uint16_t kClosedLoopFormatVersion = 4;
inline constexpr std::uint16_t kNewestFormatVersion = kClosedLoopFormatVersion;

/// Where the table goes (issue 41 §2): open_loop, the MVs themselves (every plan before
/// version 4); setpoint, offsets of the CV setpoints of the running controller (channels are
/// CVs, in CV units); mv, a dither added to the controller's MV output (channels are MVs).
enum class Excitation : std::uint8_t { open_loop = 0, setpoint = 1, mv = 2 };
/// "open_loop", "setpoint", "mv".
const char* to_text(Excitation e) noexcept;

inline constexpr std::size_t kNameCapacity = 32;         // 31 bytes + NUL
inline constexpr std::size_t kProvenanceCapacity = 128;  // 127 bytes + NUL

/// NUL-terminated text in a fixed buffer (UTF-8 bytes, no NUL inside).
template <std::size_t N>
using Text = std::array<char, N>;

/// Copies `text` into `out` with a terminating NUL; false (out unchanged) when text has
/// more than N − 1 bytes or contains a NUL.
template <std::size_t N>
bool set_text(Text<N>& out, std::string_view text) {
  if (text.size() > N - 1 || text.find('\0') != std::string_view::npos) return false;
  out.fill('\0');
  for (std::size_t i = 0; i < text.size(); ++i) out[i] = text[i];
  return true;
}

/// The text of `buffer` up to its first NUL.
template <std::size_t N>
std::string_view text_of(const Text<N>& buffer) {
  std::size_t n = 0;
  while (n < N && buffer[n] != '\0') ++n;
  return {buffer.data(), n};
}

/// One channel of the table: what it drives and where it must stay.
struct ChannelMeta {
  Text<kNameCapacity> name{};  // e.g. "reflux L", ≤ 31 bytes
  double min = 0.0;            // lowest allowed deviation, channel's engineering unit
  double max = 0.0;            // highest allowed deviation; min ≤ max
};

struct Metadata {
  std::uint16_t format_version = kFormatVersion;  // set by decode() to the file's version
  Text<kNameCapacity> design_name{};              // e.g. "prbsUnc", ≤ 31 bytes
  Text<kProvenanceCapacity> provenance{};         // plant, spec, tool version, ≤ 127 bytes
  std::uint64_t created_unix_s = 0;               // creation time, seconds since 1970 UTC
  double sample_time_min = 0.0;  // T, minutes per table row, > 0: the project's one unit of
                                 // time from the design to the run log (version 1 files
                                 // stored seconds; decode() converts them once)
  // The design's time scales (version 3; 0 = not known, and every field of a version 1 or 2
  // file): they travel with the plan into the run log's header, so identification takes
  // its time-constant bound β·τ_H (SPEC §6) from the data, not from a plant name.
  double tau_high_min = 0.0;     // τ_H, the high dominating time constant, minutes
  double beta = 0.0;             // β, settling time in units of τ_H
  double switch_time_min = 0.0;  // T_sw of the plan's PRBS (4.2.3), minutes; 0 without PRBS
  Excitation excitation = Excitation::open_loop;             // version 4 only; open_loop before
  std::array<ChannelMeta, signal::kMaxChannels> channels{};  // [0, recipe.channels) used
};

struct Plan {
  signal::Recipe recipe;
  Metadata meta;
};

/// Ok when the recipe is valid (signal::validate) and the metadata keeps its contract:
/// 1 ≤ format_version ≤ kFormatVersion, sample_time_min finite and > 0, tau_high_min, beta and
/// switch_time_min finite and ≥ 0 (0: not known), texts NUL-terminated,
/// every used channel's min and max finite with min ≤ max. The first broken rule
/// otherwise, naming the field ("meta.channels[1].min = 3, expected ≤ max = 2").
Status validate(const Plan& plan);

}  // namespace excite::plan
