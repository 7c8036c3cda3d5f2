// SPDX-License-Identifier: MIT
// excite import HISTORIAN.csv (--mv TAG… --cv TAG… | --map TAGS.toml) [--sample-time-min T]
//               [--resample hold|linear] [--max-gap-min G] [--detrend none|offset|linear]
//               [--baseline FROM:TO]
//               [--time-column NAME] -o RUN.csv
// A historian export → a run log (host/import/README.md): resampled, bad values and gaps
// flagged (never interpolated across), deviations from the baseline, optional detrend.

#include <iostream>

#include "host/cli/commands.hpp"
#include "host/cli/input_path.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/import/historian_csv.hpp"
#include "host/import/import_run.hpp"
#include "host/import/tag_map.hpp"
#include "host/output/whole_file.hpp"

namespace excite::host::cli {
namespace {

struct ImportCommandOptions {
  std::string historian_path;
  std::string output_path;
  std::vector<std::string> mv_tags, cv_tags;
  std::string map_path;
  std::string time_column;
  std::string resample = "hold";
  std::string detrend = "none";
  std::string baseline;
  historian::ImportOptions import;
};

// "FROM:TO" minutes, or "" for the first grid point.
void parse_baseline(const std::string& text, historian::ImportOptions& o) {
  if (text.empty()) return;
  const std::size_t colon = text.find(':');
  try {
    std::size_t used = 0;
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    o.baseline_from_min = std::stod(text.substr(0, colon), &used);
    if (used != colon) throw std::invalid_argument("trailing text");
    o.baseline_to_min = std::stod(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw std::invalid_argument("--baseline '" + text +
                                "'; expected FROM:TO in minutes from the data's start, e.g. 0:30");
  }
}

void run(ImportCommandOptions opt) {
  refuse_directory(opt.historian_path, "a historian export (CSV)");
  refuse_output_among_inputs(opt.output_path, {opt.historian_path, opt.map_path});
  const HumanTextAside aside(opt.output_path);
  historian::ImportOptions& o = opt.import;
  if (!opt.map_path.empty()) {
    if (!opt.mv_tags.empty() || !opt.cv_tags.empty()) {
      throw std::invalid_argument("--map " + opt.map_path +
                                  " and --mv/--cv given together; expected one of the two");
    }
    const historian::TagMap map = historian::read_tag_map(opt.map_path);
    o.mvs = map.mvs;
    o.cvs = map.cvs;
  } else {
    for (const auto& t : opt.mv_tags) o.mvs.push_back({t, t, "-"});
    for (const auto& t : opt.cv_tags) o.cvs.push_back({t, t, "-"});
  }
  if (o.mvs.empty() || o.cvs.empty()) {
    throw std::invalid_argument(std::to_string(o.mvs.size()) + " MV and " +
                                std::to_string(o.cvs.size()) +
                                " CV tags; expected at least one of each (--mv, --cv or --map)");
  }
  o.resample = opt.resample == "linear" ? historian::Resample::linear : historian::Resample::hold;
  o.detrend = opt.detrend == "offset"   ? historian::Detrend::offset
              : opt.detrend == "linear" ? historian::Detrend::linear
                                        : historian::Detrend::none;
  parse_baseline(opt.baseline, o);
  std::vector<std::string> tags;
  for (const auto& t : o.mvs) tags.push_back(t.tag);
  for (const auto& t : o.cvs) tags.push_back(t.tag);
  const historian::HistorianData data =
      historian::read_historian(opt.historian_path, opt.time_column, tags);
  const historian::ImportedRun run = historian::import_historian(data, o);
  const std::string source = std::filesystem::path(opt.historian_path).filename().string();
  write_whole_file(opt.output_path, historian::run_log_text(run, source));

  std::cout << "wrote " << opt.output_path << ": " << run.rows() << " samples of "
            << run.sample_time_min << " min, " << run.inputs.size() << " inputs, "
            << run.outputs.size() << " outputs; " << run.bad_rows << " rows flagged bad_value, "
            << run.discontinuities << " discontinuities\n";
  std::vector<historian::TagSpec> all = run.inputs;
  all.insert(all.end(), run.outputs.begin(), run.outputs.end());
  for (std::size_t a = 0; a < all.size(); ++a) {
    const bool is_input = a < run.inputs.size();
    const double base =
        is_input ? run.input_baseline[a] : run.output_baseline[a - run.inputs.size()];
    std::cout << "  " << (is_input ? "MV " : "CV ") << all[a].tag << " -> " << all[a].name << " ["
              << all[a].unit << "]: baseline " << base << ", " << run.bad_points[a] << " bad points"
              << (data.has_quality[a] ? " (quality column used)" : "");
    if (!is_input && o.detrend != historian::Detrend::none) {
      const std::size_t j = a - run.inputs.size();
      std::cout << ", removed offset " << run.removed_offset[j];
      if (o.detrend == historian::Detrend::linear) {
        std::cout << " and slope " << run.removed_slope_per_min[j] << " per min";
      }
    }
    std::cout << '\n';
  }
}

}  // namespace

void add_import_command(CLI::App& app) {
  auto opt = std::make_shared<ImportCommandOptions>();
  CLI::App* cmd =
      app.add_subcommand("import", "Convert a historian CSV export into a run log (MVs, CVs)");
  cmd->add_option("historian", opt->historian_path, "historian export (CSV)")->required();
  cmd->add_option("-o,--output", opt->output_path, "run log to write (CSV)")->required();
  cmd->add_option("--mv", opt->mv_tags, "tag of a manipulated variable (input), repeatable");
  cmd->add_option("--cv", opt->cv_tags, "tag of a controlled variable (output), repeatable");
  cmd->add_option("--map", opt->map_path, "tag map (TOML): [[mv]]/[[cv]] with tag, name, unit");
  cmd->add_option("--sample-time-min", opt->import.sample_time_min,
                  "sample time T of the run log, min (default: median timestamp spacing)")
      ->check(finite_positive());
  cmd->add_option("--resample", opt->resample, "hold (last value) or linear")
      ->capture_default_str()
      ->check(CLI::IsMember({"hold", "linear"}));
  cmd->add_option("--max-gap-min", opt->import.max_gap_min,
                  "a value older than this is a gap (bad), min (default: 1.5 sample times; "
                  "raise it for exception-based, compressed historian records)")
      ->check(finite_non_negative());
  cmd->add_option("--detrend", opt->detrend, "CVs: none, offset (mean) or linear (LS line)")
      ->capture_default_str()
      ->check(CLI::IsMember({"none", "offset", "linear"}));
  cmd->add_option("--baseline", opt->baseline,
                  "baseline window FROM:TO, min from the data's start (default: first sample)");
  cmd->add_option("--time-column", opt->time_column, "timestamp column (default: the first)");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
