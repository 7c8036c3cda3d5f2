// SPDX-License-Identifier: MIT
// parse_request: the checks excite-plant makes on a Modbus request's bytes before serving it.
#include "sim/server/modbus_request.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace excite::sim::server {
namespace {

constexpr int kMbap = 7;

// A Modbus TCP ADU: MBAP (transaction 1, protocol 0, length, unit 0xFF) and `pdu`.
std::vector<std::uint8_t> adu(const std::vector<std::uint8_t>& pdu) {
  std::vector<std::uint8_t> out = {0, 1, 0, 0, 0, static_cast<std::uint8_t>(pdu.size() + 1), 0xFF};
  out.insert(out.end(), pdu.begin(), pdu.end());
  return out;
}

ParsedRequest parse(const std::vector<std::uint8_t>& pdu) {
  const auto bytes = adu(pdu);
  return parse_request(bytes.data(), static_cast<int>(bytes.size()), kMbap, 0);
}

TEST(ModbusRequest, ReadsAddressAndCountOfAServedRequest) {
  const ParsedRequest p = parse({0x03, 0x00, 0x64, 0x00, 0x09});
  ASSERT_EQ(p.verdict, RequestVerdict::serve);
  EXPECT_EQ(p.request.function_code, 3);
  EXPECT_EQ(p.request.address, 100U);
  EXPECT_EQ(p.request.count, 9U);
  EXPECT_FALSE(p.request.write);
}

TEST(ModbusRequest, SingleRegisterWriteCountsOneRegister) {
  const ParsedRequest p = parse({0x06, 0x00, 0x6C, 0x12, 0x34});
  ASSERT_EQ(p.verdict, RequestVerdict::serve);
  EXPECT_EQ(p.request.count, 1U);
  EXPECT_TRUE(p.request.write);
}

TEST(ModbusRequest, FunctionCodeNotServedIsIllegal) {
  EXPECT_EQ(parse({0x2B, 0x0E, 0x01, 0x00}).verdict, RequestVerdict::illegal_function);
}

TEST(ModbusRequest, WrongLengthIsMalformed) {
  EXPECT_EQ(parse({0x03, 0x00, 0x64, 0x00}).verdict, RequestVerdict::malformed);
  EXPECT_EQ(parse({0x10, 0x00, 0x64, 0x00, 0x01, 0x02, 0x00}).verdict, RequestVerdict::malformed);
}

// Found by tests/fuzz/modbus_request_fuzz (15 executions/s instead of thousands): libmodbus's
// modbus_reply answers a register count out of the Modbus range only after sleeping its
// response timeout (0.5 s) and flushing the socket, stalling the single-threaded
// excite-plant. Such requests are malformed here, answered at once with exception 3.
TEST(ModbusRequest, ReadCountOutsideOneTo125IsMalformed) {
  EXPECT_EQ(parse({0x03, 0x00, 0x64, 0x00, 0x00}).verdict, RequestVerdict::malformed);
  EXPECT_EQ(parse({0x04, 0x00, 0x64, 0x00, 126}).verdict, RequestVerdict::malformed);
  EXPECT_EQ(parse({0x04, 0x00, 0x64, 0x00, 125}).verdict, RequestVerdict::serve);
}

TEST(ModbusRequest, WriteCountOutsideOneTo123OrByteCountMismatchIsMalformed) {
  EXPECT_EQ(parse({0x10, 0x00, 0x64, 0x00, 0x00, 0x00}).verdict, RequestVerdict::malformed);
  // two registers announced, one register's bytes sent
  EXPECT_EQ(parse({0x10, 0x00, 0x64, 0x00, 0x02, 0x02, 0x00, 0x01}).verdict,
            RequestVerdict::malformed);
  std::vector<std::uint8_t> many = {0x10, 0x00, 0x00, 0x00, 124, 248};
  many.resize(many.size() + 248, 0);
  EXPECT_EQ(parse(many).verdict, RequestVerdict::malformed);
  EXPECT_EQ(parse({0x10, 0x00, 0x64, 0x00, 0x01, 0x02, 0x00, 0x01}).verdict, RequestVerdict::serve);
}

}  // namespace
}  // namespace excite::sim::server
