// SPDX-License-Identifier: MIT
#pragma once
// The adaptive test's folder (excite test -o DIR, host/adaptive/README.md): the decision log
// DIR/decisions.jsonl, one event per line appended and flushed as it happens
// (decision_log.hpp's events, host/output/append_file.hpp), the operator's view
// DIR/status.txt rewritten whole after every decision and stop, and every segment's plan
// DIR/segments/segment-K.plan (the plans a gateway's segment inbox takes).

#include <filesystem>
#include <initializer_list>
#include <ostream>
#include <string>
#include <vector>

#include "host/adaptive/adaptive_test.hpp"
#include "host/output/append_file.hpp"

namespace excite::host {

/// What one test writes into its folder (a study writes only study.json).
inline constexpr std::initializer_list<const char*> kTestFolderNames = {
    "decisions.jsonl", "status.txt", "run.csv", "model.json", "segments"};

/// Creates `dir` (and its parents) after refusing it when it already holds any of `names`,
/// a link among them too, even one to nothing: a test's record is never overwritten and no
/// link is followed when writing (a planted dangling DIR/decisions.jsonl once made the test
/// create its target outside DIR). Throws std::invalid_argument "DIR: already holds NAME
/// …, expected a new or empty folder …".
void prepare_test_folder(const std::filesystem::path& dir,
                         std::initializer_list<const char*> names);

/// The observer that keeps the folder: each event to decisions.jsonl as it happens, the
/// operator's view to status.txt and to `view` (the terminal), each segment's plan to
/// segments/. `inputs`, `outputs` label the view's grade matrix.
class FolderLog final : public AdaptiveObserver {
 public:
  FolderLog(std::filesystem::path dir, std::vector<std::string> inputs,
            std::vector<std::string> outputs, std::ostream& view);

  void decided(const AdaptiveResult& so_far) override;
  void estimated(const AdaptiveResult& so_far) override;
  void stopped(const AdaptiveResult& result) override;

 private:
  void show(const AdaptiveResult& r, bool pending);

  std::filesystem::path dir_;
  std::vector<std::string> inputs_, outputs_;
  std::ostream& view_;
  AppendFile decisions_;
};

}  // namespace excite::host
