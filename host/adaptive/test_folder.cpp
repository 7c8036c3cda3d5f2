// SPDX-License-Identifier: MIT
#include "host/adaptive/test_folder.hpp"

#include <stdexcept>
#include <utility>

#include "host/adaptive/decision_log.hpp"
#include "host/design/plan_file.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host {

namespace fs = std::filesystem;

void prepare_test_folder(const fs::path& dir, std::initializer_list<const char*> names) {
  std::error_code ec;
  for (const char* name : names) {
    const fs::file_status st = fs::symlink_status(dir / name, ec);
    if (!fs::exists(st)) continue;
    throw std::invalid_argument(
        dir.string() + ": already holds " + name + (fs::is_symlink(st) ? " (a link)" : "") +
        ", expected a new or empty folder (a test's record is not overwritten, no link is "
        "followed)");
  }
  fs::create_directories(dir);
}

namespace {
// The segments folder is made before the log is opened (the order the command always had).
fs::path with_segments_folder(const fs::path& dir) {
  fs::create_directories(dir / "segments");
  return dir / "decisions.jsonl";
}
}  // namespace

FolderLog::FolderLog(fs::path dir, std::vector<std::string> inputs,
                     std::vector<std::string> outputs, std::ostream& view)
    : dir_(std::move(dir)),
      inputs_(std::move(inputs)),
      outputs_(std::move(outputs)),
      view_(view),
      decisions_(with_segments_folder(dir_)) {}

void FolderLog::decided(const AdaptiveResult& r) {
  const SegmentDecision& s = r.segments.back();
  decisions_.append(segment_event(s, r.sample_time_min).dump() + '\n');
  write_plan_file(s.plan, dir_ / "segments" / ("segment-" + std::to_string(s.index) + ".plan"));
  show(r, true);
}

void FolderLog::estimated(const AdaptiveResult& r) {
  decisions_.append(
      estimate_event(r.estimates.back(), static_cast<int>(r.estimates.size()) - 1).dump() + '\n');
}

void FolderLog::stopped(const AdaptiveResult& r) {
  decisions_.append(stop_event(r).dump() + '\n');
  show(r, false);
}

void FolderLog::show(const AdaptiveResult& r, bool pending) {
  const std::string view = operator_view(r, inputs_, outputs_, pending);
  write_whole_file(dir_ / "status.txt", view);
  view_ << view << std::flush;
}

}  // namespace excite::host
