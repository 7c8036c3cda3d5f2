// SPDX-License-Identifier: MIT
#pragma once
// The recipe: everything the signal core needs to produce an experiment's table.
// The host designs it, the plan file carries it, and host and gateway both turn it into
// the same table with the same code (SPEC §1–§3).
//
//   table(k, c) = Σ_i mix[c][i] · s_i(k)        c < channels, i < sources, k < samples
//
// where s_i is a scalar source signal (a step sequence, a PRBS or a multisine) active in
// its window [start, start + length) and zero outside it. The mixing matrix carries the
// direction design: the identity for inputs, c·V·Σ⁻¹ for gain directions (5.2.2), a
// column along v_n plus the identity for the correlated designs of Zhu (SPEC §3).
// Values are deviations from the operating point, in the channel's engineering unit.
//
// Fixed capacity, no heap: a Recipe is a plain value the gateway keeps in static storage.
// The rules a recipe must keep are checked by validate() (validate.hpp) and listed in
// firmware/signal/README.md; generate() (generate.hpp) turns it into the table.

#include <array>
#include <cstddef>
#include <cstdint>

namespace excite::signal {

inline constexpr std::uint32_t kMaxChannels = 8;
inline constexpr std::uint32_t kMaxSources = 16;
inline constexpr std::uint32_t kMaxSegments = 64;  // per step source
inline constexpr std::uint32_t kMaxLines = 4096;   // multisine lines, all sources together

/// Values (channels × samples) of the table the gateway precomputes into fixed storage at
/// start-up: 2 MiB of doubles, e.g. 4 channels × 65 536 samples. The host refuses designs
/// whose table is larger, so every plan it writes fits every gateway.
inline constexpr std::size_t kTableCapacity = std::size_t{1} << 18;

enum class SourceKind : std::uint8_t { none = 0, steps = 1, prbs = 2, multisine = 3 };

/// A piece of a step sequence: `level` held for `length` samples.
struct Segment {
  double level = 0.0;
  std::uint32_t length = 0;
};

/// Piecewise-constant sequence: segments one after another from the window start;
/// zero after the last one (4.2.1).
struct StepSource {
  std::uint32_t segment_count = 0;
  std::array<Segment, kMaxSegments> segments{};
};

/// PRBS (4.2.2): the m-sequence of `register_length` mapped 1 → +amplitude,
/// 0 → −amplitude, each bit held for `hold_samples` (T_sw / T), starting `shift` bits into
/// the sequence ("cut and shift", SPEC §1), repeating with period 2^n_r − 1 bits.
struct PrbsSource {
  std::uint8_t register_length = 0;
  double amplitude = 0.0;
  std::uint32_t hold_samples = 0;
  std::uint32_t shift = 0;
};

/// One line of a multisine on the DFT grid of a `period`-sample period:
/// amplitude · cos(2π · index · t / period + phase), t in samples from the window start.
struct Line {
  std::uint32_t index = 0;
  double amplitude = 0.0;
  double phase = 0.0;  // rad
};

/// Multisine (4.2.9): the lines lines[first_line … first_line + line_count) of the recipe.
struct MultisineSource {
  std::uint32_t period = 0;  // samples
  std::uint32_t first_line = 0;
  std::uint32_t line_count = 0;
};

struct Source {
  SourceKind kind = SourceKind::none;
  std::uint32_t start = 0;   // first sample of the window
  std::uint32_t length = 0;  // window length in samples; the source is zero outside it
  StepSource steps{};
  PrbsSource prbs{};
  MultisineSource multisine{};
};

struct Recipe {
  std::uint32_t channels = 0;  // ≤ kMaxChannels
  std::uint32_t samples = 0;   // N, table length
  std::uint32_t source_count = 0;
  std::array<Source, kMaxSources> sources{};
  std::array<std::array<double, kMaxSources>, kMaxChannels> mix{};  // mix[channel][source]
  std::uint32_t line_count = 0;
  std::array<Line, kMaxLines> lines{};
};

}  // namespace excite::signal
