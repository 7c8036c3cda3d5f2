// SPDX-License-Identifier: MIT
#include "sim/server/controller_log.hpp"

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace excite::sim::server {

ControllerLog::ControllerLog(std::string path, const std::vector<std::string>& input_names,
                             const std::vector<std::string>& output_names, double sample_time_min)
    : path_(std::move(path)), sample_time_min_(sample_time_min) {
  if (path_.empty()) return;
  file_ = std::fopen(path_.c_str(), "w");
  if (file_ == nullptr) {
    throw std::runtime_error("--controller-log " + path_ +
                             ": cannot create it: " + std::strerror(errno));
  }
  std::string header = "event,k,t_min,mode";
  for (const char* prefix : {"o_", "uc_", "du_", "st_"}) {
    for (const std::string& u : input_names) header += std::string(",") + prefix + u;
  }
  for (const std::string& y : output_names) header += ",ysp_" + y;
  header += "\n";
  if (std::fputs(header.c_str(), file_) == EOF || std::fflush(file_) != 0) {
    const std::string why = std::strerror(errno);
    std::fclose(file_);
    file_ = nullptr;
    std::remove(path_.c_str());
    throw std::runtime_error("--controller-log " + path_ + ": cannot write the header: " + why);
  }
}

ControllerLog::~ControllerLog() {
  if (file_ != nullptr) std::fclose(file_);
}

void ControllerLog::write(const char* event, std::uint64_t k, const ClosedLoop& loop) {
  if (file_ == nullptr || !failure_.empty()) return;
  const std::string_view mode = runlog::to_text(loop.mode());
  int rc = std::fprintf(file_, "%s,%llu,%.17g,%.*s", event, static_cast<unsigned long long>(k),
                        static_cast<double>(k) * sample_time_min_, static_cast<int>(mode.size()),
                        mode.data());
  for (const auto values : {loop.offsets(), loop.moves(), loop.applied()}) {
    for (const double v : values) rc = rc < 0 ? rc : std::fprintf(file_, ",%.17g", v);
  }
  for (const LoopStatus s : loop.status()) {
    rc = rc < 0 ? rc : std::fprintf(file_, ",%u", static_cast<unsigned>(s));
  }
  for (const double v : loop.setpoints()) rc = rc < 0 ? rc : std::fprintf(file_, ",%.17g", v);
  if (rc >= 0) rc = std::fputc('\n', file_) == EOF ? -1 : 0;
  if (rc < 0 || std::fflush(file_) != 0) {
    failure_ = "--controller-log " + path_ + ": cannot write sample " + std::to_string(k) + ": " +
               std::strerror(errno) + "; controller logging stopped, serving goes on";
    std::fprintf(stderr, "excite-plant: %s\n", failure_.c_str());
  }
}

}  // namespace excite::sim::server
