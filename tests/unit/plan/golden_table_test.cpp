// SPDX-License-Identifier: MIT
// Bit-identical tables across targets (firmware/signal/generate.hpp "Deterministic"): the
// CRC-32 of a table built from exactly computed inputs, recorded on x86-64 with g++ 12 and
// the same at -O1 (ASan), -O2 and -O3 -march=native (AVX2 + FMA).
// A different value on another target (a cross build under qemu, another compiler) means
// host and gateway would stream different tables there.
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <memory>
#include <vector>

#include "firmware/plan/crc32.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::plan {
namespace {

using signal::Recipe;
using signal::SourceKind;

// Every value one correctly rounded division of small integers (nothing a compiler may
// contract into a fused multiply-add): the same recipe bits on every target.
std::unique_ptr<Recipe> arithmetic_recipe() {
  auto r = std::make_unique<Recipe>();
  r->channels = 3;
  r->samples = 1000;
  r->source_count = 4;
  r->sources[0].kind = SourceKind::prbs;
  r->sources[0].length = 1000;
  r->sources[0].prbs = {7, 1.25, 4, 9};
  r->sources[1].kind = SourceKind::multisine;
  r->sources[1].start = 100;
  r->sources[1].length = 900;
  r->sources[1].multisine = {500, 0, 40};
  r->sources[2].kind = SourceKind::multisine;
  r->sources[2].length = 1000;
  r->sources[2].multisine = {999, 40, 40};
  r->sources[3].kind = SourceKind::steps;
  r->sources[3].start = 10;
  r->sources[3].length = 300;
  r->sources[3].steps.segment_count = 2;
  r->sources[3].steps.segments[0] = {0.5, 100};
  r->sources[3].steps.segments[1] = {-0.75, 150};
  r->line_count = 80;
  for (std::uint32_t l = 0; l < 80; ++l) {
    const auto phase_hundredths =
        static_cast<double>(37 * static_cast<int>(l) - 300 * static_cast<int>(l % 5));
    r->lines[l] = {(7 * l + 1) % 249, 1.0 / (l + 1.0), phase_hundredths / 100.0};
  }
  for (std::uint32_t c = 0; c < 3; ++c) {
    for (std::uint32_t i = 0; i < 4; ++i)
      r->mix[c][i] = static_cast<double>(1 + c + 2 * i) / static_cast<double>(3 + i);
  }
  return r;
}

TEST(GoldenTable, OfAnArithmeticRecipeHasTheRecordedChecksum) {
  const auto recipe = arithmetic_recipe();
  std::vector<double> table(3 * 1000);
  std::vector<double> scratch(signal::scratch_size(*recipe));
  ASSERT_TRUE(signal::generate(*recipe, {table.data(), 3, 1000}, scratch));
  std::vector<std::uint8_t> bytes;
  for (const double v : table) {
    const auto bits = std::bit_cast<std::uint64_t>(v);
    for (int b = 0; b < 8; ++b) bytes.push_back(static_cast<std::uint8_t>(bits >> (8 * b)));
  }
  EXPECT_EQ(crc32(bytes), 0xDC220D7DU);
}

}  // namespace
}  // namespace excite::plan
