// SPDX-License-Identifier: MIT
#include "host/identify/run_log_input.hpp"

#include <stdexcept>

#include "host/identify/run_log_limits.hpp"
#include "host/output/input_path.hpp"

namespace excite::host {
namespace {

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ",") + s;
  return out;
}

}  // namespace

runlog::RunLog read_log(const std::string& path) {
  refuse_directory(path, "a run log (CSV)");
  runlog::ReadResult r = runlog::read_run_log(path, limited_read_options());
  if (!r.ok()) throw std::invalid_argument(r.error->to_string());
  return std::move(r.log);
}

std::vector<runlog::RunLog> read_pooled_logs(const std::vector<std::string>& paths) {
  if (paths.size() == 1) return {read_log(paths.front())};
  std::vector<runlog::RunLog> runs;
  std::size_t total = 0;
  for (const std::string& path : paths) {
    refuse_directory(path, "a run log (CSV)");
    runlog::ReadResult r =
        runlog::read_run_log(path, limited_read_options({}, kMaxRunRows - total));
    if (r.over_row_limit) {
      throw std::invalid_argument(
          path + ": more than " + std::to_string(kMaxRunRows) + " data rows in the " +
          std::to_string(paths.size()) + " runs together (counted up to this one), expected at " +
          "most " + std::to_string(kMaxRunRows) + " in total (host/README.md, Limits)");
    }
    if (!r.ok()) throw std::invalid_argument(r.error->to_string());
    total += r.log.rows();
    runs.push_back(std::move(r.log));
  }
  return runs;
}

void check_pooled_headers(const std::vector<runlog::RunLog>& runs,
                          const std::vector<std::string>& paths, bool allow_mixed) {
  if (allow_mixed || runs.empty()) return;
  const runlog::RunLog& first = runs.front();
  for (std::size_t r = 1; r < runs.size() && r < paths.size(); ++r) {
    const runlog::RunLog& log = runs[r];
    const auto refuse = [&](const std::string& field, const std::string& value,
                            const std::string& expected) {
      throw std::invalid_argument(paths[r] + ": " + field + " = '" + value + "', expected '" +
                                  expected + "' as in " + paths.front() +
                                  " to identify the runs together (--allow-mixed pools them "
                                  "anyway)");
    };
    if (log.plant != first.plant) refuse("plant", log.plant, first.plant);
    if (log.input_units != first.input_units)
      refuse("input units", joined(log.input_units), joined(first.input_units));
    if (log.output_units != first.output_units)
      refuse("output units", joined(log.output_units), joined(first.output_units));
  }
}

SegmentedRun read_segmented_run(const std::string& path, const FlagRule& rule) {
  SegmentedRun run{read_log(path), {}};
  run.data = stack_runs({&run.log}, {path}, rule);
  return run;
}

Eigen::Index scored_in(const SampleLayout& layout, const Segment& s) {
  Eigen::Index n = 0;
  for (Eigen::Index k = s.begin; k < s.end; ++k) n += layout.weight(k) > 0.0 ? 1 : 0;
  return n;
}

std::vector<Segment> scored_segments(const SampleLayout& layout) {
  std::vector<Segment> out;
  for (const Segment& s : layout.segments) {
    if (scored_in(layout, s) > 0) out.push_back(s);
  }
  return out;
}

Eigen::MatrixXd simulate_per_segment(const IdentifiedModel& model, const Eigen::MatrixXd& U,
                                     const SampleLayout& layout) {
  Eigen::MatrixXd Y_hat = Eigen::MatrixXd::Zero(U.rows(), model.outputs);
  for (const Segment& s : layout.segments) {
    Y_hat.middleRows(s.begin, s.end - s.begin) =
        simulate(model, U.middleRows(s.begin, s.end - s.begin));
  }
  return Y_hat;
}

}  // namespace excite::host
