// SPDX-License-Identifier: MIT
#include "firmware/plan/codec.hpp"

#include <memory>

#include "firmware/plan/bytes.hpp"
#include "firmware/plan/crc32.hpp"

namespace excite::plan {
namespace {

using detail::ByteReader;
using detail::ByteWriter;
using signal::kMaxChannels;
using signal::kMaxLines;
using signal::kMaxSegments;
using signal::kMaxSources;
using signal::Recipe;
using signal::Source;
using signal::SourceKind;
using U64 = unsigned long long;

// Sizes of the pieces of version 1 (README.md "Format, version 1").
constexpr std::size_t kMetaFixedSize = 8 + 8 + 3 * 8;  // created, T, τ_H, β, T_sw (v3)
constexpr std::size_t kCountsSize = 4 * 4;             // channels, samples, sources, lines
constexpr std::size_t kChannelFixedSize = 8 + 8;       // min, max (+ name)
constexpr std::size_t kSourceHeaderSize = 1 + 4 + 4;   // kind, start, length
constexpr std::size_t kSegmentSize = 8 + 4;            // level, length
constexpr std::size_t kPrbsSize = 1 + 8 + 4 + 4;       // n_r, amplitude, hold, shift
constexpr std::size_t kMultisineSize = 4 + 4 + 4;      // period, first line, line count
constexpr std::size_t kLineSize = 4 + 8 + 8;           // index, amplitude, phase

template <std::size_t N>
std::size_t text_size(const Text<N>& text) {
  return 1 + text_of(text).size();
}

std::size_t source_size(const Source& source) {
  switch (source.kind) {
    case SourceKind::steps:
      return kSourceHeaderSize + 4 + source.steps.segment_count * kSegmentSize;
    case SourceKind::prbs:
      return kSourceHeaderSize + kPrbsSize;
    default:
      return kSourceHeaderSize + kMultisineSize;
  }
}

template <std::size_t N>
void write_text(ByteWriter& w, const Text<N>& text) {
  const std::string_view s = text_of(text);
  w.u8(static_cast<std::uint8_t>(s.size()));
  for (const char ch : s) w.u8(static_cast<std::uint8_t>(ch));
}

void write_source(ByteWriter& w, const Source& source) {
  w.u8(static_cast<std::uint8_t>(source.kind));
  w.u32(source.start);
  w.u32(source.length);
  switch (source.kind) {
    case SourceKind::steps:
      w.u32(source.steps.segment_count);
      for (std::uint32_t s = 0; s < source.steps.segment_count; ++s) {
        w.f64(source.steps.segments[s].level);
        w.u32(source.steps.segments[s].length);
      }
      break;
    case SourceKind::prbs:
      w.u8(source.prbs.register_length);
      w.f64(source.prbs.amplitude);
      w.u32(source.prbs.hold_samples);
      w.u32(source.prbs.shift);
      break;
    default:
      w.u32(source.multisine.period);
      w.u32(source.multisine.first_line);
      w.u32(source.multisine.line_count);
      break;
  }
}

Status truncated_in(const ByteReader& r, const char* what) {
  return Status::error(StatusCode::truncated,
                       "payload ends at byte %llu inside %s, expected more bytes (counts "
                       "beyond the payload)",
                       U64{r.position()}, what);
}

template <std::size_t N>
Status read_text(ByteReader& r, Text<N>& out, const char* field) {
  const std::uint8_t length = r.u8();
  if (!r.ok()) return truncated_in(r, field);
  if (length > N - 1) {
    return Status::error(StatusCode::capacity_exceeded, "%s length = %u bytes, expected ≤ %zu",
                         field, unsigned{length}, N - 1);
  }
  out.fill('\0');
  for (std::size_t i = 0; i < length; ++i) {
    const std::uint8_t ch = r.u8();
    if (ch == 0 && r.ok()) {
      return Status::error(StatusCode::invalid_field,
                           "%s has a NUL at byte %zu, expected text without NUL", field, i);
    }
    out[i] = static_cast<char>(ch);
  }
  if (!r.ok()) return truncated_in(r, field);
  return {};
}

Status read_source(ByteReader& r, std::uint32_t i, Source& source) {
  const std::uint8_t kind = r.u8();
  source.start = r.u32();
  source.length = r.u32();
  if (!r.ok()) return truncated_in(r, "a source header");
  switch (kind) {
    case static_cast<std::uint8_t>(SourceKind::steps): {
      source.kind = SourceKind::steps;
      const std::uint32_t count = r.u32();
      if (!r.ok()) return truncated_in(r, "a step source");
      if (count > kMaxSegments) {
        return Status::error(StatusCode::capacity_exceeded,
                             "sources[%u].steps.segment_count = %u, expected ≤ %u", i, count,
                             kMaxSegments);
      }
      source.steps.segment_count = count;
      for (std::uint32_t s = 0; s < count; ++s) {
        source.steps.segments[s].level = r.f64();
        source.steps.segments[s].length = r.u32();
      }
      if (!r.ok()) return truncated_in(r, "step segments");
      return {};
    }
    case static_cast<std::uint8_t>(SourceKind::prbs):
      source.kind = SourceKind::prbs;
      source.prbs.register_length = r.u8();
      source.prbs.amplitude = r.f64();
      source.prbs.hold_samples = r.u32();
      source.prbs.shift = r.u32();
      if (!r.ok()) return truncated_in(r, "a PRBS source");
      return {};
    case static_cast<std::uint8_t>(SourceKind::multisine):
      source.kind = SourceKind::multisine;
      source.multisine.period = r.u32();
      source.multisine.first_line = r.u32();
      source.multisine.line_count = r.u32();
      if (!r.ok()) return truncated_in(r, "a multisine source");
      return {};
    default:
      return Status::error(StatusCode::invalid_field,
                           "sources[%u].kind = %u, expected 1 (steps), 2 (prbs) or 3 (multisine)",
                           i, unsigned{kind});
  }
}

Status read_payload(ByteReader& r, Plan& plan) {
  Metadata& meta = plan.meta;
  Recipe& recipe = plan.recipe;
  meta.created_unix_s = r.u64();
  // T: minutes since version 2; version 1 stored seconds (the one conversion, here).
  const double sample_time = r.f64();
  meta.sample_time_min = meta.format_version == 1 ? sample_time / 60.0 : sample_time;
  if (meta.format_version >= 3) {  // the design's time scales; older files: 0, not known
    meta.tau_high_min = r.f64();
    meta.beta = r.f64();
    meta.switch_time_min = r.f64();
  }
  if (meta.format_version >= 4) {  // the closed-loop plan's excitation (1 setpoint, 2 mv)
    const std::uint8_t e = r.u8();
    if (r.ok() && (e == 0 || e > 2)) {
      return Status::error(StatusCode::invalid_field,
                           "meta.excitation = %u, expected 1 (setpoint) or 2 (mv) in a version "
                           "4 plan",
                           unsigned{e});
    }
    meta.excitation = static_cast<Excitation>(e);
  }
  if (!r.ok()) return truncated_in(r, "the metadata");
  if (Status s = read_text(r, meta.design_name, "meta.design_name"); !s) return s;
  if (Status s = read_text(r, meta.provenance, "meta.provenance"); !s) return s;

  recipe.channels = r.u32();
  recipe.samples = r.u32();
  recipe.source_count = r.u32();
  recipe.line_count = r.u32();
  if (!r.ok()) return truncated_in(r, "the recipe's counts");
  if (recipe.channels == 0 || recipe.channels > kMaxChannels) {
    return Status::error(StatusCode::capacity_exceeded, "channels = %u, expected 1…%u",
                         recipe.channels, kMaxChannels);
  }
  if (recipe.source_count > kMaxSources) {
    return Status::error(StatusCode::capacity_exceeded, "source_count = %u, expected ≤ %u",
                         recipe.source_count, kMaxSources);
  }
  if (recipe.line_count > kMaxLines) {
    return Status::error(StatusCode::capacity_exceeded, "line_count = %u, expected ≤ %u",
                         recipe.line_count, kMaxLines);
  }

  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    ChannelMeta& ch = meta.channels[c];
    if (Status s = read_text(r, ch.name, "meta.channels[].name"); !s) return s;
    ch.min = r.f64();
    ch.max = r.f64();
  }
  if (!r.ok()) return truncated_in(r, "the channel limits");
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    for (std::uint32_t i = 0; i < recipe.source_count; ++i) recipe.mix[c][i] = r.f64();
  }
  if (!r.ok()) return truncated_in(r, "the mixing matrix");
  for (std::uint32_t i = 0; i < recipe.source_count; ++i) {
    if (Status s = read_source(r, i, recipe.sources[i]); !s) return s;
  }
  for (std::uint32_t l = 0; l < recipe.line_count; ++l) {
    recipe.lines[l].index = r.u32();
    recipe.lines[l].amplitude = r.f64();
    recipe.lines[l].phase = r.f64();
  }
  if (!r.ok()) return truncated_in(r, "the multisine lines");
  if (r.remaining() != 0) {
    return Status::error(StatusCode::invalid_field,
                         "payload has %llu bytes after the last line, expected none",
                         U64{r.remaining()});
  }
  return {};
}

std::uint32_t read_u32_le(std::span<const std::uint8_t> in, std::size_t at) {
  return std::uint32_t{in[at]} | std::uint32_t{in[at + 1]} << 8U |
         std::uint32_t{in[at + 2]} << 16U | std::uint32_t{in[at + 3]} << 24U;
}

Status check_envelope(std::span<const std::uint8_t> in) {
  const std::size_t magic_seen = std::min(in.size(), kMagic.size());
  for (std::size_t i = 0; i < magic_seen; ++i) {
    if (in[i] != kMagic[i]) {
      return Status::error(StatusCode::bad_magic,
                           "byte %zu = 0x%02x, expected 0x%02x of the plan magic \\x89EXPLAN\\n "
                           "(not a plan file)",
                           i, unsigned{in[i]}, unsigned{kMagic[i]});
    }
  }
  if (in.size() < kHeaderSize + kTrailerSize) {
    return Status::error(StatusCode::truncated,
                         "plan file of %zu bytes, expected at least %zu (header and checksum)",
                         in.size(), kHeaderSize + kTrailerSize);
  }
  const auto version = static_cast<std::uint16_t>(in[8] | in[9] << 8U);
  if (version == 0 || version > kNewestFormatVersion) {
    return Status::error(StatusCode::unsupported_version,
                         "plan file has format version %u, this build reads versions 1…%u",
                         unsigned{version}, unsigned{kNewestFormatVersion});
  }
  const std::uint64_t payload = read_u32_le(in, 12);
  const std::uint64_t total = kHeaderSize + payload + kTrailerSize;
  if (in.size() < total) {
    return Status::error(StatusCode::truncated,
                         "plan file of %zu bytes, expected %llu (header announces a payload of "
                         "%llu bytes)",
                         in.size(), U64{total}, U64{payload});
  }
  if (in.size() > total) {
    return Status::error(StatusCode::invalid_field,
                         "plan file of %zu bytes, expected %llu (header announces a payload of "
                         "%llu bytes; extra bytes after the checksum)",
                         in.size(), U64{total}, U64{payload});
  }
  const std::size_t body = kHeaderSize + static_cast<std::size_t>(payload);
  const std::uint32_t stored = read_u32_le(in, body);
  const std::uint32_t computed = crc32(in.first(body));
  if (stored != computed) {
    return Status::error(StatusCode::checksum_mismatch,
                         "stored CRC-32 = 0x%08x, expected 0x%08x computed over the first %zu "
                         "bytes (file corrupted)",
                         stored, computed, body);
  }
  const auto flags = static_cast<std::uint16_t>(in[10] | in[11] << 8U);
  if (flags != 0) {
    return Status::error(StatusCode::invalid_field,
                         "header flags = 0x%04x, expected 0 (reserved in version %u)",
                         unsigned{flags}, unsigned{version});
  }
  return {};
}

}  // namespace

std::size_t encoded_size(const Plan& plan) {
  const Recipe& recipe = plan.recipe;
  const bool closed = plan.meta.excitation != Excitation::open_loop;
  std::size_t size = kHeaderSize + kMetaFixedSize + (closed ? 1 : 0) +
                     text_size(plan.meta.design_name) + text_size(plan.meta.provenance) +
                     kCountsSize;
  for (std::uint32_t c = 0; c < recipe.channels && c < kMaxChannels; ++c) {
    size += text_size(plan.meta.channels[c].name) + kChannelFixedSize;
  }
  size += std::size_t{recipe.channels} * recipe.source_count * 8;
  for (std::uint32_t i = 0; i < recipe.source_count && i < kMaxSources; ++i) {
    size += source_size(recipe.sources[i]);
  }
  size += std::size_t{recipe.line_count} * kLineSize;
  return size + kTrailerSize;
}

std::size_t max_encoded_size() {
  const std::size_t biggest_source = kSourceHeaderSize + 4 + kMaxSegments * kSegmentSize;
  return kHeaderSize + kMetaFixedSize + 1 + kNameCapacity + kProvenanceCapacity + kCountsSize +
         kMaxChannels * (kNameCapacity + kChannelFixedSize) + kMaxChannels * kMaxSources * 8 +
         kMaxSources * biggest_source + kMaxLines * kLineSize + kTrailerSize;
}

EncodeResult encode(const Plan& plan, std::span<std::uint8_t> out) {
  if (Status s = validate(plan); !s) return {s};
  const std::size_t size = encoded_size(plan);
  if (out.size() < size) {
    return {Status::error(StatusCode::capacity_exceeded,
                          "output buffer of %zu bytes, expected ≥ %zu (encoded_size(plan))",
                          out.size(), size)};
  }
  const Recipe& recipe = plan.recipe;
  ByteWriter w(out.first(size));
  w.bytes(kMagic);
  const bool closed = plan.meta.excitation != Excitation::open_loop;
  w.u16(closed ? kClosedLoopFormatVersion : kFormatVersion);
  w.u16(0);  // flags, reserved
  w.u32(static_cast<std::uint32_t>(size - kHeaderSize - kTrailerSize));

  w.u64(plan.meta.created_unix_s);
  w.f64(plan.meta.sample_time_min);
  w.f64(plan.meta.tau_high_min);
  w.f64(plan.meta.beta);
  w.f64(plan.meta.switch_time_min);
  if (closed) w.u8(static_cast<std::uint8_t>(plan.meta.excitation));
  write_text(w, plan.meta.design_name);
  write_text(w, plan.meta.provenance);
  w.u32(recipe.channels);
  w.u32(recipe.samples);
  w.u32(recipe.source_count);
  w.u32(recipe.line_count);
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    write_text(w, plan.meta.channels[c].name);
    w.f64(plan.meta.channels[c].min);
    w.f64(plan.meta.channels[c].max);
  }
  for (std::uint32_t c = 0; c < recipe.channels; ++c) {
    for (std::uint32_t i = 0; i < recipe.source_count; ++i) w.f64(recipe.mix[c][i]);
  }
  for (std::uint32_t i = 0; i < recipe.source_count; ++i) write_source(w, recipe.sources[i]);
  for (std::uint32_t l = 0; l < recipe.line_count; ++l) {
    w.u32(recipe.lines[l].index);
    w.f64(recipe.lines[l].amplitude);
    w.f64(recipe.lines[l].phase);
  }
  w.u32(crc32(out.first(w.position())));
  return {Status{}, w.position()};
}

Status decode(std::span<const std::uint8_t> in, Plan& out, bool closed_loop_allowed) {
  std::construct_at(&out);  // a default Plan in place; the 100 kB value never hits the stack
  Status status = check_envelope(in);
  if (status) {
    const std::size_t payload = in.size() - kHeaderSize - kTrailerSize;
    ByteReader reader(in.subspan(kHeaderSize, payload));
    out.meta.format_version = static_cast<std::uint16_t>(in[8] | in[9] << 8U);
    status = read_payload(reader, out);
    if (status) status = validate(out);
    if (status && out.meta.excitation != Excitation::open_loop && !closed_loop_allowed) {
      status = Status::error(StatusCode::invalid_field,
                             "meta.excitation = %s (a closed-loop plan, version 4), expected an "
                             "open-loop plan: this reader applies the table as MV moves",
                             to_text(out.meta.excitation));
    }
  }
  if (!status) std::construct_at(&out);
  return status;
}

}  // namespace excite::plan
