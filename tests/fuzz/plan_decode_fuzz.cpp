// SPDX-License-Identifier: MIT
// Fuzzes the plan decoder (firmware/plan, plan::decode), the gateway's and the host's one
// reader of plan files. Each input is decoded twice:
//   1. as it is: magic, version, length, checksum and everything behind them;
//   2. with the header's payload length and the trailing CRC-32 recomputed, so that
//      mutations of the payload reach the field checks instead of dying at the checksum.
// Property: whatever decodes re-encodes, and decode → encode → decode → encode gives the
// same bytes (encode is deterministic and writes every field the decoder reads), i.e. the
// same plan.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "check.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/plan/crc32.hpp"

namespace {

using excite::plan::Plan;

// Plans are ~100 kB: allocated once, reused for every input.
Plan& first_plan() {
  static const auto plan = std::make_unique<Plan>();
  return *plan;
}
Plan& second_plan() {
  static const auto plan = std::make_unique<Plan>();
  return *plan;
}

void put_u32_le(std::vector<std::uint8_t>& bytes, std::size_t at, std::uint32_t value) {
  for (std::size_t i = 0; i < 4; ++i) bytes[at + i] = static_cast<std::uint8_t>(value >> (8 * i));
}

void check_round_trip(const Plan& decoded) {
  std::vector<std::uint8_t> first(excite::plan::max_encoded_size());
  const auto encoded = excite::plan::encode(decoded, first);
  EXCITE_FUZZ_CHECK(encoded.status.is_ok(), "a decoded plan must encode");
  EXCITE_FUZZ_CHECK(encoded.size == excite::plan::encoded_size(decoded),
                    "encode writes encoded_size() bytes");
  first.resize(encoded.size);

  Plan& again = second_plan();
  EXCITE_FUZZ_CHECK(excite::plan::decode(first, again).is_ok(), "an encoded plan must decode");
  std::vector<std::uint8_t> second(excite::plan::max_encoded_size());
  const auto reencoded = excite::plan::encode(again, second);
  EXCITE_FUZZ_CHECK(reencoded.status.is_ok(), "a re-decoded plan must encode");
  second.resize(reencoded.size);
  EXCITE_FUZZ_CHECK(first == second, "decode -> encode -> decode changed the plan");
}

void decode_and_check(std::span<const std::uint8_t> bytes) {
  Plan& plan = first_plan();
  if (excite::plan::decode(bytes, plan).is_ok()) check_round_trip(plan);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> input(data, size);
  decode_and_check(input);

  constexpr std::size_t header = excite::plan::kHeaderSize;
  constexpr std::size_t trailer = excite::plan::kTrailerSize;
  if (size < header + trailer) return 0;
  std::vector<std::uint8_t> fixed(input.begin(), input.end());
  const std::size_t payload = size - header - trailer;
  put_u32_le(fixed, 12, static_cast<std::uint32_t>(payload));
  put_u32_le(fixed, header + payload,
             excite::plan::crc32(std::span<const std::uint8_t>(fixed).first(header + payload)));
  decode_and_check(fixed);
  return 0;
}
