// SPDX-License-Identifier: MIT
// Fuzzes excite-plant's handling of Modbus TCP requests on the register image of the example
// configuration sim/server/examples/alatiqi4x4.toml (float32 setpoints in three word orders,
// a scaled int16 one, input limits, heartbeat, echo and control block).
//
// The server's request handling (PlantServer::handle) answers on a socket; its checks of the
// request bytes are the pure function parse_request (sim/server/modbus_request.hpp), factored
// out for this harness. Each input is a sequence of frames, each a length byte n and n bytes
// of PDU (function code first; at most 253), sent on a fresh image in the order handle()
// uses: parse_request; for a write, RegisterImage::check_write against the input limits
// (refused: exception 3, nothing written); libmodbus's modbus_reply on the image's mapping,
// the reply going to one end of a socketpair; note_write; read_setpoints.
// Contracts checked: parse_request reads only the frame (ASan); a reply comes back for every
// request, echoes the transaction id, and carries the function code (or it | 0x80 with an
// exception); a request not served gets exception 1, a malformed one or a refused write
// exception 3; and, the safety property, every setpoint the plant reads after accepted writes
// lies within the input limits (within a float32 register's rounding).

#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"
#include "sim/server/modbus_request.hpp"
#include "sim/server/register_image.hpp"
#include "sim/server/server_config.hpp"
#include "sim/server/server_layout.hpp"

namespace {

using excite::sim::server::ParsedRequest;
using excite::sim::server::RequestVerdict;

constexpr int kMbap = 7;  // transaction, protocol, length, unit
constexpr std::size_t kMaxPdu = 253;
constexpr int kMaxFrames = 32;

struct Fixture {
  excite::sim::server::ServerLayout layout;
  std::vector<double> input_baseline;
  std::vector<double> output_baseline;
  std::vector<double> input_min;
  std::vector<double> input_max;
  modbus_t* ctx = nullptr;
  int server_end = -1;  // libmodbus writes replies here
  int client_end = -1;  // the harness reads them here
};

Fixture* fixture = nullptr;

Fixture* make_fixture() {
  std::ifstream in(EXCITE_FUZZ_SERVER_EXAMPLE);
  std::stringstream text;
  text << in.rdbuf();
  const auto config =
      excite::sim::server::parse_server_config(text.str(), EXCITE_FUZZ_SERVER_EXAMPLE);
  auto* f = new Fixture;
  const int inputs = static_cast<int>(config.registers.map.setpoints.size());
  const int outputs = static_cast<int>(config.registers.map.values.size());
  f->layout = excite::sim::server::compile_layout(config, inputs, outputs, false);
  f->input_baseline = config.plant.input_baseline;
  f->output_baseline = config.plant.output_baseline;
  f->input_min = config.plant.input_min;
  f->input_max = config.plant.input_max;
  if (f->input_min.empty() || f->input_baseline.size() != f->input_min.size()) {
    std::fprintf(stderr, "%s: expected input limits and baselines\n", EXCITE_FUZZ_SERVER_EXAMPLE);
    std::abort();
  }
  int ends[2];
  if (socketpair(AF_UNIX, SOCK_STREAM, 0, ends) != 0) std::abort();
  f->server_end = ends[0];
  f->client_end = ends[1];
  f->ctx = modbus_new_tcp("127.0.0.1", 502);  // never connects: replies go to server_end
  modbus_set_socket(f->ctx, f->server_end);
  return f;
}

// The reply to the request with transaction id `tid` and function code `fc`; its exception
// code, or 0 for a normal reply.
int take_reply(std::uint16_t tid, std::uint8_t fc) {
  std::array<std::uint8_t, 512> reply{};
  const ssize_t n = recv(fixture->client_end, reply.data(), reply.size(), MSG_DONTWAIT);
  EXCITE_FUZZ_CHECK(n >= kMbap + 1, "every request gets a reply");
  EXCITE_FUZZ_CHECK(((reply[0] << 8) | reply[1]) == tid, "the reply echoes the transaction id");
  const std::size_t length = static_cast<std::size_t>((reply[4] << 8) | reply[5]);
  EXCITE_FUZZ_CHECK(static_cast<std::size_t>(n) == 6 + length, "the MBAP length is the reply's");
  // libmodbus answers an exception with fc + 0x80 in a byte: a request code ≥ 0x80 (reserved
  // for exception replies) comes back as fc − 0x80 (noticed here, left as libmodbus does it).
  if (reply[7] == static_cast<std::uint8_t>(fc + 0x80)) {
    EXCITE_FUZZ_CHECK(n == kMbap + 2, "an exception reply is fc | 0x80 and its code");
    return reply[8];
  }
  EXCITE_FUZZ_CHECK(reply[7] == fc, "a normal reply carries the request's function code");
  return 0;
}

void check_setpoints(excite::sim::server::RegisterImage& image) {
  std::vector<double> u(fixture->input_baseline.size());
  image.read_setpoints(u.data());
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double min = fixture->input_min[i];
    const double max = fixture->input_max[i];
    const double tolerance = (std::abs(min) + std::abs(max)) * 0x1p-23;  // float32 rounding
    EXCITE_FUZZ_CHECK(u[i] >= min - tolerance && u[i] <= max + tolerance,
                      "the plant reads a setpoint outside its input limits");
  }
}

// One request in the order PlantServer::handle takes it; returns after checking the reply.
void serve(excite::sim::server::RegisterImage& image, std::uint8_t* adu, int length,
           std::uint16_t tid) {
  const std::uint8_t fc = adu[kMbap];
  const ParsedRequest parsed = excite::sim::server::parse_request(adu, length, kMbap, 0);
  if (parsed.verdict == RequestVerdict::illegal_function) {
    modbus_reply_exception(fixture->ctx, adu, MODBUS_EXCEPTION_ILLEGAL_FUNCTION);
    EXCITE_FUZZ_CHECK(take_reply(tid, fc) == MODBUS_EXCEPTION_ILLEGAL_FUNCTION,
                      "a function code not served gets exception 1");
    return;
  }
  if (parsed.verdict == RequestVerdict::malformed) {
    modbus_reply_exception(fixture->ctx, adu, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
    EXCITE_FUZZ_CHECK(take_reply(tid, fc) == MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE,
                      "a malformed request gets exception 3");
    return;
  }
  excite::sim::server::ModbusRequest request = parsed.request;
  if (request.write) {
    const bool single = request.function_code == MODBUS_FC_WRITE_SINGLE_REGISTER;
    request.count = single ? 1U : std::min<std::uint32_t>(request.count, adu[kMbap + 5] / 2U);
    const auto refused =
        image.check_write(request.address, request.count, adu + kMbap + (single ? 3 : 6),
                          fixture->input_min, fixture->input_max);
    if (refused) {
      modbus_reply_exception(fixture->ctx, adu, MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE);
      EXCITE_FUZZ_CHECK(take_reply(tid, fc) == MODBUS_EXCEPTION_ILLEGAL_DATA_VALUE,
                        "a write outside the limits gets exception 3");
      return;
    }
  }
  modbus_reply(fixture->ctx, adu, length, image.mapping());
  take_reply(tid, fc);
  if (request.write) image.note_write(request.address, request.count);
  check_setpoints(image);
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fixture = make_fixture();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  excite::sim::server::RegisterImage image(fixture->layout, fixture->input_baseline,
                                           fixture->output_baseline);
  std::size_t at = 0;
  for (std::uint16_t tid = 1; at < size && tid <= kMaxFrames; ++tid) {
    const std::size_t announced = data[at++];
    const std::size_t pdu = std::min({announced, size - at, kMaxPdu});
    if (pdu == 0) continue;
    // The ADU exactly as excite-plant assembles it from the socket (MBAP, unit, PDU).
    std::vector<std::uint8_t> adu(kMbap + pdu);
    adu[0] = static_cast<std::uint8_t>(tid >> 8);
    adu[1] = static_cast<std::uint8_t>(tid);
    adu[4] = static_cast<std::uint8_t>((pdu + 1) >> 8);
    adu[5] = static_cast<std::uint8_t>(pdu + 1);
    adu[6] = 0xFF;
    std::copy(data + at, data + at + pdu, adu.begin() + kMbap);
    at += pdu;
    serve(image, adu.data(), static_cast<int>(adu.size()), tid);
  }
  return 0;
}
