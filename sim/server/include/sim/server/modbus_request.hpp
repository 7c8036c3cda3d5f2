// SPDX-License-Identifier: MIT
#pragma once
// The checks excite-plant makes on one Modbus request before serving it, as a pure function
// of the request's bytes (no socket, no libmodbus context): which function code, whether its
// length is right, the register range it addresses. PlantServer::handle acts on the result;
// tests/fuzz/modbus_request_fuzz feeds it raw frames.

#include <cstdint>

namespace excite::sim::server {

/// A request excite-plant serves: function code 3, 4, 6 or 16 and its register range.
struct ModbusRequest {
  int function_code = 0;
  std::uint32_t address = 0;
  std::uint32_t count = 0;  // registers addressed; 1 for function code 6
  bool write = false;       // function codes 6 and 16
};

enum class RequestVerdict {
  serve,             // well formed, a served function code: `request` is set
  illegal_function,  // a function code not served: answer exception 1 (illegal function)
  malformed,         // a served function code with the wrong length or register count
                     // (exception 3)
};

struct ParsedRequest {
  RequestVerdict verdict = RequestVerdict::malformed;
  ModbusRequest request;
};

/// Parses the request in `adu[0, length)`: `header` bytes before the function code (7, the
/// Modbus TCP MBAP header with the unit; 1, the RTU address) and `crc` bytes after the PDU
/// (2 for RTU, 0 for TCP). Requires length ≥ header + 1 (the function code is present).
/// Function codes 3, 4 and 6 are exactly 5 bytes of PDU after the code; 16 is 6 bytes plus
/// the byte count it announces. Counts: 1…125 registers read (3, 4), 1…123 written (16) with
/// a byte count of twice that — the Modbus limits, checked here because libmodbus's
/// modbus_reply answers a violation only after sleeping its response timeout. Reads no byte
/// at or beyond `length`.
ParsedRequest parse_request(const std::uint8_t* adu, int length, int header, int crc);

}  // namespace excite::sim::server
