// SPDX-License-Identifier: MIT
#include "host/design/plan_file.hpp"

#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/plan/codec.hpp"
#include "host/output/input_file.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host {

void write_plan_file(const plan::Plan& plan, const std::filesystem::path& path) {
  std::vector<std::uint8_t> bytes(plan::encoded_size(plan));
  const plan::EncodeResult encoded = plan::encode(plan, bytes);
  if (!encoded.status) throw std::runtime_error(path.string() + ": " + encoded.status.message());
  bytes.resize(encoded.size);

  write_whole_file(path,
                   std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::unique_ptr<plan::Plan> read_plan_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {  // the message every command gives a folder
    throw std::invalid_argument(path.string() + ": is a directory, expected a plan file");
  }
  // A regular file no larger than the largest plan (issue 40 §5): a FIFO or /dev/zero is
  // refused by name, never waited on or read without end.
  const std::string text = read_input_file(path, plan::max_encoded_size(), "a plan file");
  const std::vector<std::uint8_t> bytes(text.begin(), text.end());
  auto result = std::make_unique<plan::Plan>();
  // Closed-loop plans too (version 4): excite simulate runs them under a controller and
  // refuses them without one; inspect shows them.
  const plan::Status status = plan::decode(bytes, *result, /*closed_loop_allowed=*/true);
  if (!status) throw std::invalid_argument(path.string() + ": " + status.message());
  const std::uint64_t values = std::uint64_t{result->recipe.channels} * result->recipe.samples;
  if (values > signal::kTableCapacity) {  // what the gateway can play; bounds inspect's memory
    throw std::invalid_argument(
        path.string() + ": channels x samples = " + std::to_string(result->recipe.channels) +
        " x " + std::to_string(result->recipe.samples) + " = " + std::to_string(values) +
        " values, expected at most " + std::to_string(signal::kTableCapacity) +
        " (the gateway's table, firmware/signal/recipe.hpp kTableCapacity)");
  }
  return result;
}

}  // namespace excite::host
