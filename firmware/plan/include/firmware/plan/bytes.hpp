// SPDX-License-Identifier: MIT
#pragma once
// Little-endian byte packing of the plan file, one explicit byte at a time (no memcpy of
// structs, so the file layout is independent of the host's padding and byte order).

#include <bit>
#include <cstddef>
#include <cstdint>
#include <span>

namespace excite::plan::detail {

/// Appends to a byte buffer whose size the caller has checked beforehand (encoded_size()).
class ByteWriter {
 public:
  explicit ByteWriter(std::span<std::uint8_t> out) : out_(out) {}

  void u8(std::uint8_t v) { out_[pos_++] = v; }
  void u16(std::uint16_t v) { uint_le(v, 2); }
  void u32(std::uint32_t v) { uint_le(v, 4); }
  void u64(std::uint64_t v) { uint_le(v, 8); }
  void f64(double v) { u64(std::bit_cast<std::uint64_t>(v)); }
  void bytes(std::span<const std::uint8_t> b) {
    for (const std::uint8_t x : b) u8(x);
  }
  std::size_t position() const { return pos_; }

 private:
  void uint_le(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  std::span<std::uint8_t> out_;
  std::size_t pos_ = 0;
};

/// Reads from a byte buffer; once a read would pass the end, every read yields 0 and
/// ok() stays false, so a parser checks ok() once per section.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> in) : in_(in) {}

  std::uint8_t u8() { return static_cast<std::uint8_t>(uint_le(1)); }
  std::uint16_t u16() { return static_cast<std::uint16_t>(uint_le(2)); }
  std::uint32_t u32() { return static_cast<std::uint32_t>(uint_le(4)); }
  std::uint64_t u64() { return uint_le(8); }
  double f64() { return std::bit_cast<double>(u64()); }

  bool ok() const { return ok_; }
  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return in_.size() - pos_; }

 private:
  std::uint64_t uint_le(int n) {
    if (!ok_ || remaining() < static_cast<std::size_t>(n)) {
      ok_ = false;
      return 0;
    }
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= std::uint64_t{in_[pos_++]} << (8 * i);
    return v;
  }
  std::span<const std::uint8_t> in_;
  std::size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace excite::plan::detail
