// SPDX-License-Identifier: MIT
#include "host/design/plan_file.hpp"

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "firmware/plan/codec.hpp"

namespace excite::host {

void write_plan_file(const plan::Plan& plan, const std::filesystem::path& path) {
  std::vector<std::uint8_t> bytes(plan::encoded_size(plan));
  const plan::EncodeResult encoded = plan::encode(plan, bytes);
  if (!encoded.status) throw std::runtime_error(path.string() + ": " + encoded.status.message());
  bytes.resize(encoded.size);

  std::filesystem::path temporary = path;
  temporary += ".partial";
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
    out.flush();
    if (!out) throw std::runtime_error(temporary.string() + ": cannot be written");
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec) {
    std::filesystem::remove(temporary);
    throw std::runtime_error(path.string() + ": cannot be written (" + ec.message() + ")");
  }
}

std::unique_ptr<plan::Plan> read_plan_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path.string() + ": cannot be read");
  const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                        std::istreambuf_iterator<char>());
  auto result = std::make_unique<plan::Plan>();
  const plan::Status status = plan::decode(bytes, *result);
  if (!status) throw std::invalid_argument(path.string() + ": " + status.message());
  return result;
}

}  // namespace excite::host
