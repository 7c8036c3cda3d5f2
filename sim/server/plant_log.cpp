// SPDX-License-Identifier: MIT
#include "sim/server/plant_log.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "firmware/runlog/format.hpp"

namespace excite::sim::server {

namespace {

constexpr const char* kPlan = "none (excite-plant)";

std::string_view unit_of(const std::vector<std::string>& units, std::size_t i) {
  return i < units.size() && !units[i].empty() ? std::string_view(units[i]) : std::string_view("-");
}

}  // namespace

PlantLog::PlantLog(PlantLogSpec spec) : spec_(std::move(spec)) {
  if (spec_.path.empty()) return;
  file_ = std::fopen(spec_.path.c_str(), "w");
  if (file_ == nullptr) {
    throw std::runtime_error("--log " + spec_.path + ": " + std::strerror(errno));
  }
  try {
    for (std::size_t i = 0; i < spec_.input_names.size(); ++i) {
      inputs_.push_back({spec_.input_names[i], unit_of(spec_.input_units, i)});
    }
    for (std::size_t j = 0; j < spec_.output_names.size(); ++j) {
      outputs_.push_back({spec_.output_names[j], unit_of(spec_.output_units, j)});
    }
    buffer_.resize(
        std::max<std::size_t>(runlog::max_row_chars(inputs_.size(), outputs_.size()), 4096));
    producer_ = "excite-plant " + std::string(runlog::kVersion);
    header_.emplace(runlog::Header{spec_.plant_description, kPlan, spec_.sample_time_min, inputs_,
                                   outputs_, producer_, spec_.time_scales});
    rows_.emplace(fileno(file_));
    const runlog::WriteResult f = runlog::format_header(*header_, buffer_);
    if (f.status != runlog::WriteStatus::ok) {
      throw std::runtime_error("--log " + spec_.path + ": " + f.message);
    }
    if (!rows_->append(std::span<const char>(buffer_.data(), f.length))) {
      char why[192];
      throw std::runtime_error("--log " + spec_.path + ": cannot write the header: " +
                               runlog::describe_errno(rows_->error(), why, sizeof why));
    }
  } catch (...) {
    std::fclose(file_);
    file_ = nullptr;
    std::remove(spec_.path.c_str());
    throw;
  }
}

PlantLog::~PlantLog() {
  if (file_ != nullptr) std::fclose(file_);
}

void PlantLog::write(std::uint64_t k, std::span<const double> du, std::span<const double> u,
                     std::span<const double> dy) {
  if (!header_ || !failure_.empty()) return;
  const runlog::Row row{
      static_cast<double>(k) * spec_.sample_time_min, k, du, u, dy, 0, runlog::RunState::unknown};
  const runlog::WriteResult f = runlog::format_row(*header_, row, buffer_);
  if (f.status != runlog::WriteStatus::ok) {
    throw std::runtime_error("--log " + spec_.path + ": sample " + std::to_string(k) + ": " +
                             f.message);
  }
  // One row in write(2) calls of its own: a failed write (disk full, file-size limit) cuts
  // the file back to its last whole row; logging stops, serving goes on (issue 19).
  if (!rows_->append(std::span<const char>(buffer_.data(), f.length))) {
    char why[192];
    failure_ = "--log " + spec_.path + ": cannot write sample " + std::to_string(k) + ": " +
               runlog::describe_errno(rows_->error(), why, sizeof why) +
               "; logging stopped, the log is whole up to its last full row (" + std::to_string(k) +
               " samples); serving goes on";
    std::fprintf(stderr, "excite-plant: %s\n", failure_.c_str());
    std::fflush(stderr);
  }
}

}  // namespace excite::sim::server
