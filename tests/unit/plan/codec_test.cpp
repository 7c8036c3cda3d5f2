// SPDX-License-Identifier: MIT
#include "firmware/plan/codec.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "example_plan.hpp"
#include "firmware/plan/crc32.hpp"
#include "firmware/signal/generate.hpp"
#include "plan_table.hpp"

namespace excite::plan {
namespace {

using Bytes = std::vector<std::uint8_t>;
using testing::example_plan;

Bytes encoded(const Plan& plan) {
  Bytes out(max_encoded_size());
  const EncodeResult result = encode(plan, out);
  EXPECT_TRUE(result.status) << result.status.message();
  out.resize(result.size);
  return out;
}

using testing::table_of;

void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i)
    b[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}

std::uint32_t u32_at(const Bytes& b, std::size_t at) {
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < 4; ++i) v |= std::uint32_t{b[at + i]} << (8 * i);
  return v;
}

// Rewrites the trailing CRC-32 so that only the deliberate change is wrong with the file.
void reseal(Bytes& b) {
  put_u32(b, b.size() - 4, crc32(std::span<const std::uint8_t>(b).first(b.size() - 4)));
}

// Offset of the recipe's counts in the example plan's file (README.md, "Format"):
// header 16, created 8, sample time 8, time scales 3 × 8 (v3), two texts of 1 + length bytes.
std::size_t counts_offset() {
  return 16 + 8 + 8 + 24 + 1 + std::strlen(testing::kDesignName) + 1 +
         std::strlen(testing::kProvenance);
}

// Offset of sources[0] (a PRBS): after the counts, the 4 channels' name and limits, and
// the 4 × 5 mix.
std::size_t first_source_offset(const Plan& plan) {
  std::size_t at = counts_offset() + 16;
  for (std::uint32_t c = 0; c < 4; ++c) at += 1 + text_of(plan.meta.channels[c].name).size() + 16;
  return at + 4 * 5 * 8;
}

TEST(PlanCodec, ReEncodesADecodedPlanByteForByte) {
  const auto plan = example_plan();
  const Bytes first = encoded(*plan);
  auto decoded = std::make_unique<Plan>();
  const Status status = decode(first, *decoded);
  ASSERT_TRUE(status) << status.message();
  EXPECT_EQ(encoded(*decoded), first);
}

TEST(PlanCodec, DecodedPlanGeneratesTheSameTableBitForBit) {
  const auto plan = example_plan();
  auto decoded = std::make_unique<Plan>();
  ASSERT_TRUE(decode(encoded(*plan), *decoded));
  const std::vector<double> original = table_of(plan->recipe);
  const std::vector<double> again = table_of(decoded->recipe);
  ASSERT_EQ(original.size(), again.size());
  EXPECT_EQ(0, std::memcmp(original.data(), again.data(), original.size() * sizeof(double)));
}

TEST(PlanCodec, DecodedPlanKeepsTheMetadata) {
  const auto plan = example_plan();
  auto decoded = std::make_unique<Plan>();
  ASSERT_TRUE(decode(encoded(*plan), *decoded));
  EXPECT_EQ(decoded->meta.format_version, kFormatVersion);
  EXPECT_EQ(text_of(decoded->meta.design_name), testing::kDesignName);
  EXPECT_EQ(text_of(decoded->meta.provenance), testing::kProvenance);
  EXPECT_EQ(decoded->meta.created_unix_s, 1'795'000'000U);
  EXPECT_EQ(decoded->meta.sample_time_min, 1.0);
  for (std::uint32_t c = 0; c < 4; ++c) {
    EXPECT_EQ(text_of(decoded->meta.channels[c].name), text_of(plan->meta.channels[c].name));
    EXPECT_EQ(decoded->meta.channels[c].min, plan->meta.channels[c].min);
    EXPECT_EQ(decoded->meta.channels[c].max, plan->meta.channels[c].max);
  }
}

TEST(PlanCodec, WritesTheHeaderAndChecksumOfTheDocumentedLayout) {
  const Bytes file = encoded(*example_plan());
  const Bytes header(file.begin(), file.begin() + 12);
  EXPECT_EQ(header, (Bytes{0x89, 'E', 'X', 'P', 'L', 'A', 'N', '\n', 3, 0, 0, 0}));
  const std::uint32_t payload = u32_at(file, 12);
  EXPECT_EQ(payload, file.size() - 20);
  const std::uint32_t stored = u32_at(file, file.size() - 4);
  EXPECT_EQ(stored, crc32(std::span<const std::uint8_t>(file).first(file.size() - 4)));
  // created_unix_s, little-endian, first in the payload.
  EXPECT_EQ(file[16], 1'795'000'000U & 0xFFU);
  EXPECT_EQ(file[17], (1'795'000'000U >> 8U) & 0xFFU);
}

TEST(PlanCodec, WritesOnlyTheUsedSourcesLinesSegmentsAndChannels) {
  const auto plan = example_plan();
  auto cluttered = example_plan();
  cluttered->recipe.sources[9].kind = signal::SourceKind::steps;  // source_count = 5
  cluttered->recipe.sources[4].steps.segments[40] = {3.0, 7};     // segment_count = 3
  cluttered->recipe.lines[3000] = {5, 1.0, 0.5};                  // line_count = 120
  cluttered->recipe.mix[6][2] = 2.0;                              // channels = 4
  set_text(cluttered->meta.channels[5].name, "unused");
  const Bytes file = encoded(*plan);
  EXPECT_EQ(encoded(*cluttered), file);
  EXPECT_EQ(file.size(), encoded_size(*plan));
  // 20 header+CRC, 16 meta + 24 time scales (v3), 2 + texts, 16 counts, 4 channels, 4 × 5 mix, 2
  // PRBS, 2 multisines, 1 step source of 3 segments, 120 lines.
  const std::size_t expected = 20 + 16 + 24 + 2 + std::strlen(testing::kDesignName) +
                               std::strlen(testing::kProvenance) + 16 + (4 * 17 + 8 + 7 + 11 + 6) +
                               4 * 5 * 8 + 2 * (9 + 17) + 2 * (9 + 12) + (9 + 4 + 3 * 12) +
                               120 * 20;
  EXPECT_EQ(file.size(), expected);
}

TEST(PlanCodec, FullestPlanNeedsExactlyMaxEncodedSize) {
  auto plan = std::make_unique<Plan>();
  signal::Recipe& r = plan->recipe;
  r.channels = signal::kMaxChannels;
  r.samples = 1000;
  r.source_count = signal::kMaxSources;
  for (auto& s : r.sources) {
    s.kind = signal::SourceKind::steps;
    s.length = 1000;
    s.steps.segment_count = signal::kMaxSegments;
  }
  r.line_count = signal::kMaxLines;
  plan->meta.sample_time_min = 1.0 / 60.0;
  set_text(plan->meta.design_name, std::string(31, 'd'));
  set_text(plan->meta.provenance, std::string(127, 'p'));
  for (auto& ch : plan->meta.channels) set_text(ch.name, std::string(31, 'c'));
  plan->meta.excitation = Excitation::setpoint;  // a closed-loop plan: one byte more
  EXPECT_EQ(encoded(*plan).size(), max_encoded_size());
}

// Version 4 (issue 41 §2): a closed-loop plan carries its excitation in one byte after the
// time scales; an open-loop plan is still written as version 3, byte for byte.
TEST(PlanCodec, ClosedLoopPlanIsVersion4AndReadsBackItsExcitation) {
  auto plan = example_plan();
  const Bytes open = encoded(*plan);
  EXPECT_EQ(open[8], 3);
  for (const Excitation e : {Excitation::setpoint, Excitation::mv}) {
    plan->meta.excitation = e;
    const Bytes closed = encoded(*plan);
    EXPECT_EQ(closed[8], 4);
    EXPECT_EQ(closed.size(), open.size() + 1);
    EXPECT_EQ(closed[16 + 40], static_cast<std::uint8_t>(e));  // after created, T, τ_H, β, T_sw
    auto out = std::make_unique<Plan>();
    ASSERT_TRUE(decode(closed, *out, true)) << decode(closed, *out, true).message();
    EXPECT_EQ(out->meta.excitation, e);
    EXPECT_EQ(out->meta.format_version, 4);
    EXPECT_EQ(encoded(*out), closed);  // re-encodes to the same bytes
  }
}

TEST(PlanCodec, AReaderOfMvMovesRefusesAClosedLoopPlanByName) {
  auto plan = example_plan();
  plan->meta.excitation = Excitation::setpoint;
  auto out = std::make_unique<Plan>();
  const Status status = decode(encoded(*plan), *out);
  EXPECT_EQ(status.code(), StatusCode::invalid_field);
  EXPECT_EQ(std::string(status.message()),
            "meta.excitation = setpoint (a closed-loop plan, version 4), expected an open-loop "
            "plan: this reader applies the table as MV moves");
}

TEST(PlanCodec, RefusesTheFileTruncatedAtEveryLength) {
  const Bytes file = encoded(*example_plan());
  auto out = std::make_unique<Plan>();
  for (std::size_t n = 0; n < file.size(); ++n) {
    const Status status = decode(std::span<const std::uint8_t>(file).first(n), *out);
    ASSERT_EQ(status.code(), StatusCode::truncated) << "length " << n << ": " << status.message();
  }
}

TEST(PlanCodec, RefusesEverySingleBitFlip) {
  Bytes file = encoded(*example_plan());
  auto out = std::make_unique<Plan>();
  for (std::size_t byte = 0; byte < file.size(); ++byte) {
    for (int bit = 0; bit < 8; ++bit) {
      file[byte] ^= static_cast<std::uint8_t>(1U << bit);
      const Status status = decode(file, *out);
      file[byte] ^= static_cast<std::uint8_t>(1U << bit);
      ASSERT_FALSE(status) << "byte " << byte << " bit " << bit;
    }
  }
}

TEST(PlanCodec, LeavesADefaultPlanWhenItRefuses) {
  Bytes file = encoded(*example_plan());
  file[100] ^= 0x10U;
  auto out = example_plan();
  EXPECT_EQ(decode(file, *out).code(), StatusCode::checksum_mismatch);
  EXPECT_EQ(out->recipe.channels, 0U);
  EXPECT_EQ(out->recipe.source_count, 0U);
  EXPECT_EQ(text_of(out->meta.design_name), "");
}

TEST(PlanCodec, RefusesANewerVersionNamingTheFilesAndTheBuildsVersion) {
  Bytes file = encoded(*example_plan());
  file[8] = 5;
  reseal(file);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::unsupported_version);
  EXPECT_EQ(std::string(status.message()),
            "plan file has format version 5, this build reads versions 1…4");
}

// Version 2 stores T in minutes (the project's unit); version 1 stored seconds and is still
// read, converted once in decode(). Version 3 adds the design's time scales after T.
double f64_at(const Bytes& b, std::size_t at) {
  std::uint64_t bits = 0;
  for (std::size_t i = 0; i < 8; ++i) bits |= std::uint64_t{b[at + i]} << (8U * i);
  double v = 0.0;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

void put_f64(Bytes& b, std::size_t at, double v) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &v, sizeof v);
  for (std::size_t i = 0; i < 8; ++i) b[at + i] = static_cast<std::uint8_t>(bits >> (8U * i));
}

constexpr std::size_t kSampleTimeOffset = 16 + 8;  // header, created_unix_s

constexpr std::size_t kTimeScalesOffset = kSampleTimeOffset + 8;  // v3: τ_H, β, T_sw

// The same plan as a file of an older version: version `v`, without the v3 time scales.
Bytes as_version(Bytes file, std::uint8_t v) {
  file[8] = v;
  file.erase(file.begin() + kTimeScalesOffset, file.begin() + kTimeScalesOffset + 24);
  put_u32(file, 12, static_cast<std::uint32_t>(file.size() - 20));
  reseal(file);
  return file;
}

TEST(PlanCodec, Version3WritesTheSampleTimeInMinutesAndTheDesignsTimeScales) {
  auto plan = example_plan();
  plan->meta.sample_time_min = 0.5;
  plan->meta.tau_high_min = 50.0;
  plan->meta.beta = 3.0;
  plan->meta.switch_time_min = 16.0;
  const Bytes file = encoded(*plan);
  EXPECT_EQ(file[8] | file[9] << 8U, 3);
  EXPECT_EQ(f64_at(file, kSampleTimeOffset), 0.5);
  EXPECT_EQ(f64_at(file, kTimeScalesOffset), 50.0);
  EXPECT_EQ(f64_at(file, kTimeScalesOffset + 8), 3.0);
  EXPECT_EQ(f64_at(file, kTimeScalesOffset + 16), 16.0);
  auto out = std::make_unique<Plan>();
  ASSERT_TRUE(decode(file, *out));
  EXPECT_EQ(out->meta.format_version, 3U);
  EXPECT_EQ(out->meta.sample_time_min, 0.5);
  EXPECT_EQ(out->meta.tau_high_min, 50.0);
  EXPECT_EQ(out->meta.beta, 3.0);
  EXPECT_EQ(out->meta.switch_time_min, 16.0);
}

TEST(PlanCodec, ReadsVersion2WithTheTimeScalesNotKnown) {
  auto plan = example_plan();
  plan->meta.sample_time_min = 0.5;
  const Bytes v3 = encoded(*plan);
  auto out = std::make_unique<Plan>();
  const Status status = decode(as_version(v3, 2), *out);
  ASSERT_TRUE(status) << status.message();
  EXPECT_EQ(out->meta.format_version, 2U);
  EXPECT_EQ(out->meta.sample_time_min, 0.5);
  EXPECT_EQ(out->meta.tau_high_min, 0.0);
  EXPECT_EQ(out->meta.beta, 0.0);
  EXPECT_EQ(out->meta.switch_time_min, 0.0);
  out->meta.format_version = kFormatVersion;
  EXPECT_EQ(encoded(*out), v3);  // re-encoded, it is the version-3 file
}

TEST(PlanCodec, ReadsVersion1WhoseSampleTimeIsInSeconds) {
  auto plan = example_plan();
  plan->meta.sample_time_min = 0.5;
  const Bytes v3 = encoded(*plan);
  Bytes v1 = as_version(v3, 1);  // the same plan as a version-1 file: version 1, T = 30 s
  put_f64(v1, kSampleTimeOffset, 30.0);
  reseal(v1);
  auto out = std::make_unique<Plan>();
  const Status status = decode(v1, *out);
  ASSERT_TRUE(status) << status.message();
  EXPECT_EQ(out->meta.format_version, 1U);
  EXPECT_EQ(out->meta.sample_time_min, 0.5);
  EXPECT_EQ(out->recipe.samples, plan->recipe.samples);
  out->meta.format_version = kFormatVersion;
  EXPECT_EQ(encoded(*out), v3);  // re-encoded, it is the version-3 file
}

TEST(PlanCodec, RefusesANegativeOrNonFiniteTimeScaleNamingIt) {
  auto plan = example_plan();
  plan->meta.beta = -1.0;
  const Status status = validate(*plan);
  EXPECT_EQ(status.code(), StatusCode::invalid_field);
  EXPECT_EQ(std::string(status.message()),
            "meta.beta = -1, expected a finite number ≥ 0 (0: not known)");
}

TEST(PlanCodec, RefusesBadMagic) {
  Bytes file = encoded(*example_plan());
  file[1] = 'e';
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::bad_magic);
  EXPECT_EQ(std::string(status.message()),
            "byte 1 = 0x65, expected 0x45 of the plan magic \\x89EXPLAN\\n (not a plan file)");
}

TEST(PlanCodec, RefusesBytesAfterTheChecksum) {
  Bytes file = encoded(*example_plan());
  file.push_back(0);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::invalid_field);
  EXPECT_NE(std::string(status.message()).find("extra bytes after the checksum"), std::string::npos)
      << status.message();
}

TEST(PlanCodec, RefusesAChecksumMismatchNamingBothValues) {
  Bytes file = encoded(*example_plan());
  file[file.size() - 1] ^= 0x80U;
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::checksum_mismatch);
  EXPECT_EQ(std::string(status.message()).rfind("stored CRC-32 = 0x", 0), 0U) << status.message();
}

TEST(PlanCodec, RefusesASourceCountBeyondCapacity) {
  Bytes file = encoded(*example_plan());
  put_u32(file, counts_offset() + 8, 17);
  reseal(file);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::capacity_exceeded);
  EXPECT_EQ(std::string(status.message()), "source_count = 17, expected ≤ 16");
}

TEST(PlanCodec, RefusesALineCountBeyondCapacity) {
  Bytes file = encoded(*example_plan());
  put_u32(file, counts_offset() + 12, 4097);
  reseal(file);
  auto out = std::make_unique<Plan>();
  EXPECT_EQ(std::string(decode(file, *out).message()), "line_count = 4097, expected ≤ 4096");
}

TEST(PlanCodec, RefusesCountsThatReachBeyondThePayload) {
  Bytes file = encoded(*example_plan());
  put_u32(file, counts_offset() + 12, 121);  // one line more than written
  reseal(file);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::truncated);
  EXPECT_NE(std::string(status.message()).find("inside the multisine lines"), std::string::npos)
      << status.message();
}

TEST(PlanCodec, RefusesAnInvalidRecipeInAWellFormedFileWithValidatesMessage) {
  const auto plan = example_plan();
  Bytes file = encoded(*plan);
  const std::size_t at = first_source_offset(*plan);
  ASSERT_EQ(file[at], static_cast<std::uint8_t>(signal::SourceKind::prbs));
  ASSERT_EQ(file[at + 9], 8);  // register_length
  file[at + 9] = 40;
  reseal(file);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::invalid_field);
  EXPECT_EQ(std::string(status.message()), "sources[0].prbs.register_length = 40, expected 2…31");
}

TEST(PlanCodec, RefusesAnUnknownSourceKind) {
  const auto plan = example_plan();
  Bytes file = encoded(*plan);
  file[first_source_offset(*plan)] = 7;
  reseal(file);
  auto out = std::make_unique<Plan>();
  EXPECT_EQ(std::string(decode(file, *out).message()),
            "sources[0].kind = 7, expected 1 (steps), 2 (prbs) or 3 (multisine)");
}

TEST(PlanCodec, RefusesATextLongerThanItsField) {
  Bytes file = encoded(*example_plan());
  file[56] = 32;  // length byte of meta.design_name (after T and the v3 time scales)
  reseal(file);
  auto out = std::make_unique<Plan>();
  const Status status = decode(file, *out);
  EXPECT_EQ(status.code(), StatusCode::capacity_exceeded);
  EXPECT_EQ(std::string(status.message()), "meta.design_name length = 32 bytes, expected ≤ 31");
}

TEST(PlanCodec, EncodeRefusesABufferShorterThanTheFile) {
  const auto plan = example_plan();
  Bytes out(encoded_size(*plan) - 1, 0xAA);
  const EncodeResult result = encode(*plan, out);
  EXPECT_EQ(result.status.code(), StatusCode::capacity_exceeded);
  EXPECT_EQ(result.size, 0U);
  for (const std::uint8_t b : out) ASSERT_EQ(b, 0xAA);  // nothing written
}

TEST(PlanCodec, EncodeRefusesAnInvalidPlan) {
  auto plan = example_plan();
  plan->meta.sample_time_min = 0.0;
  Bytes out(max_encoded_size());
  const EncodeResult result = encode(*plan, out);
  EXPECT_EQ(std::string(result.status.message()),
            "meta.sample_time_min = 0, expected a finite number > 0");
}

}  // namespace
}  // namespace excite::plan
