// SPDX-License-Identifier: MIT
// excite import HISTORIAN.csv (--mv TAG… --cv TAG… | --map TAGS.toml) [--sample-time-min T]
//               [--resample hold|linear] [--max-gap-min G] [--detrend none|offset|linear]
//               [--baseline FROM:TO] [--time-column NAME | --time-column-per-tag | --long]
//               [--delimiter C] [--decimal-comma] [--time-format FMT] [--time-zone ZONE]
//               [--epoch s|ms|us] [--header-rows N] [--good-confidence C]
//               [--from TIME] [--to TIME] -o RUN.csv
// A historian export → a run log (host/import/README.md): resampled, bad values and gaps
// flagged (never interpolated across), deviations from the baseline, optional detrend.

#include <iostream>

#include "firmware/runlog/format.hpp"
#include "host/cli/commands.hpp"
#include "host/cli/number_checks.hpp"
#include "host/cli/output_target.hpp"
#include "host/identify/run_log_limits.hpp"
#include "host/import/csv_text.hpp"
#include "host/import/historian_csv.hpp"
#include "host/import/import_run.hpp"
#include "host/import/tag_map.hpp"
#include "host/output/input_path.hpp"
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
  std::string delimiter = ",";
  std::string epoch;
  historian::CsvOptions csv;
  historian::ImportOptions import;
};

// "," ";" "tab" "\t" "|" …: one character.
char delimiter_of(const std::string& text) {
  if (text == "tab" || text == "\\t" || text == "\t") return '\t';
  if (text == "semicolon") return ';';
  if (text == "comma") return ',';
  if (text.size() != 1 || text == "\"" || text == "\n" || text == "\r") {
    throw std::invalid_argument("--delimiter = '" + text +
                                "', expected one character (',', ';', '|') or tab");
  }
  return text[0];
}

// A tag's unit from the export's units row when the tag map names none.
void take_units(const historian::HistorianData& data, std::vector<historian::TagSpec>& specs,
                std::size_t first) {
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const std::string& unit = data.units[first + i];
    if (unit.empty() || specs[i].unit != "-") continue;
    if (!runlog::valid_unit(unit)) {
      throw std::invalid_argument(data.file + ":" + std::to_string(data.units_line) + ": unit of " +
                                  specs[i].tag + " = '" + unit +
                                  "', expected no spaces, commas or '=' (give the tag's unit "
                                  "in a --map file)");
    }
    specs[i].unit = unit;
  }
}

// "FROM:TO" minutes, or "auto" (the default, also "") for a steady window before the first MV
// move, else the run's mean (import_run.hpp, auto_baseline).
void parse_baseline(const std::string& text, historian::ImportOptions& o) {
  o.baseline_auto = text.empty() || text == "auto";
  if (o.baseline_auto) return;
  const std::size_t colon = text.find(':');
  try {
    std::size_t used = 0;
    if (colon == std::string::npos) throw std::invalid_argument("no colon");
    o.baseline_from_min = std::stod(text.substr(0, colon), &used);
    if (used != colon) throw std::invalid_argument("trailing text");
    o.baseline_to_min = std::stod(text.substr(colon + 1), &used);
    if (used != text.size() - colon - 1) throw std::invalid_argument("trailing text");
  } catch (const std::exception&) {
    throw std::invalid_argument(
        "--baseline '" + text +
        "', expected auto or FROM:TO in minutes from the data's start, e.g. "
        "0:30");
  }
}

// The MV and CV tags, from --map or from --mv and --cv (not both); at least one of each.
void take_tags(const ImportCommandOptions& opt, historian::ImportOptions& o) {
  if (!opt.map_path.empty()) {
    if (!opt.mv_tags.empty() || !opt.cv_tags.empty()) {
      throw std::invalid_argument("--map " + opt.map_path +
                                  " and --mv/--cv given together, expected one of the two");
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
                                " CV tags, expected at least one of each (--mv, --cv or --map)");
  }
}

// The export's layout from the options (delimiter, decimal comma, long or wide, time column,
// epoch), checked for combinations that contradict each other; the run-log limits.
void take_csv_layout(ImportCommandOptions& opt) {
  historian::CsvOptions& csv = opt.csv;
  csv.delimiter = delimiter_of(opt.delimiter);
  if (csv.decimal_comma && csv.delimiter == ',') {
    throw std::invalid_argument(
        "--decimal-comma with --delimiter ',', expected another delimiter (';' in most "
        "European exports)");
  }
  if (csv.long_format && (csv.time_column_per_tag || !opt.time_column.empty())) {
    throw std::invalid_argument(
        "--long with --time-column or --time-column-per-tag, expected one layout (--long: "
        "TAG,TIME,VALUE[,QUALITY] by position)");
  }
  csv.time_column = opt.time_column;
  csv.epoch = opt.epoch == "s"    ? historian::Epoch::s
              : opt.epoch == "ms" ? historian::Epoch::ms
              : opt.epoch == "us" ? historian::Epoch::us
                                  : historian::Epoch::automatic;
  // Absolute values within half the limit keep their deviations within it.
  csv.max_value = kMaxRunValue / 2.0;
  csv.max_samples = 20 * kMaxRunRows;
}

// What was written: the run's size and flags, then per tag its baseline, bad points and cells,
// and what detrending removed.
void print_imported(const ImportCommandOptions& opt, const historian::HistorianData& data,
                    const historian::ImportedRun& run) {
  if (!run.start_at_rest) std::cerr << "excite: warning: " << run.baseline_note << '\n';
  std::cout << "wrote " << opt.output_path << ": " << run.rows() << " samples of "
            << run.sample_time_min << " min, " << run.inputs.size() << " inputs, "
            << run.outputs.size() << " outputs; " << run.bad_rows << " rows flagged bad_value, "
            << run.discontinuities << " discontinuities\n";
  const historian::Detrend detrend = opt.import.detrend;
  std::vector<historian::TagSpec> all = run.inputs;
  all.insert(all.end(), run.outputs.begin(), run.outputs.end());
  for (std::size_t a = 0; a < all.size(); ++a) {
    const bool is_input = a < run.inputs.size();
    const double base =
        is_input ? run.input_baseline[a] : run.output_baseline[a - run.inputs.size()];
    std::cout << "  " << (is_input ? "MV " : "CV ") << all[a].tag << " -> " << all[a].name << " ["
              << all[a].unit << "]: baseline " << base << ", " << run.bad_points[a] << " bad points"
              << (data.has_quality[a] ? " (quality column used)" : "");
    if (!data.bad_examples[a].empty()) {
      std::cout << "; " << data.bad_cells[a] << " bad cells, not numbers:";
      for (const auto& b : data.bad_examples[a]) {
        std::cout << " line " << b.line << " " << historian::quote_cell(b.text);
      }
    }
    if (!is_input && detrend != historian::Detrend::none) {
      const std::size_t j = a - run.inputs.size();
      std::cout << ", removed offset " << run.removed_offset[j];
      if (detrend == historian::Detrend::linear) {
        std::cout << " and slope " << run.removed_slope_per_min[j] << " per min";
      }
    }
    std::cout << '\n';
  }
}

void run(ImportCommandOptions opt) {
  refuse_directory(opt.historian_path, "a historian export (CSV)");
  refuse_output_among_inputs(opt.output_path, {opt.historian_path, opt.map_path});
  const HumanTextAside aside(opt.output_path);
  historian::ImportOptions& o = opt.import;
  if (o.time_scales.tau_high_min > 0.0 && o.time_scales.beta == 0.0) o.time_scales.beta = 3.0;
  take_tags(opt, o);
  o.resample = opt.resample == "linear" ? historian::Resample::linear : historian::Resample::hold;
  o.detrend = opt.detrend == "offset"   ? historian::Detrend::offset
              : opt.detrend == "linear" ? historian::Detrend::linear
                                        : historian::Detrend::none;
  parse_baseline(opt.baseline, o);
  std::vector<std::string> tags;
  for (const auto& t : o.mvs) tags.push_back(t.tag);
  for (const auto& t : o.cvs) tags.push_back(t.tag);
  take_csv_layout(opt);
  o.max_rows = kMaxRunRows;
  const historian::HistorianData data =
      historian::read_historian(opt.historian_path, tags, opt.csv);
  take_units(data, o.mvs, 0);
  take_units(data, o.cvs, o.mvs.size());
  const historian::ImportedRun run = historian::import_historian(data, o);
  const std::string source = std::filesystem::path(opt.historian_path).filename().string();
  write_whole_file(opt.output_path, historian::run_log_text(run, source));
  print_imported(opt, data, run);
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
                  "auto (default: a steady window before the first MV move, else the run's "
                  "mean, the start then flagged not at rest) or a window FROM:TO, min from the "
                  "data's start");
  cmd->add_option("--time-column", opt->time_column, "timestamp column (default: the first)");
  cmd->add_option("--tau-high", opt->import.time_scales.tau_high_min,
                  "tau_H of the test's design, min: written to the run log, where identify takes "
                  "its time-constant bound beta x tau_H from")
      ->check(finite_positive());
  cmd->add_option("--beta", opt->import.time_scales.beta,
                  "settling time in units of tau_H (default 3 with --tau-high)")
      ->check(finite_positive());
  cmd->add_flag("--time-column-per-tag", opt->csv.time_column_per_tag,
                "columns in TIME,VALUE pairs, one time column per tag (PI archive dumps; a "
                "repeated time column name is detected without it)");
  cmd->add_flag("--long", opt->csv.long_format,
                "long format: columns TAG,TIME,VALUE[,QUALITY], one sample per row");
  cmd->add_option("--delimiter", opt->delimiter, "field separator: ',', ';', '|' or tab")
      ->capture_default_str();
  cmd->add_flag("--decimal-comma", opt->csv.decimal_comma,
                "numbers written 1.234,5 (European locale; use with --delimiter ';')");
  cmd->add_option("--time-format", opt->csv.time_format,
                  "strftime-style timestamp form, e.g. '%m/%d/%Y %I:%M:%S %p' "
                  "(default: ISO 8601 or epoch)");
  cmd->add_option("--time-zone", opt->csv.time_zone,
                  "IANA zone of local (naive) timestamps, e.g. Europe/Berlin (default: as UTC)");
  cmd->add_option("--epoch", opt->epoch, "unit of epoch timestamps (default: s, checked)")
      ->check(CLI::IsMember({"s", "ms", "us"}));
  cmd->add_option("--header-rows", opt->csv.header_rows,
                  "rows after the header to skip (units, descriptions; a 'Units' row is read)");
  cmd->add_option("--good-confidence", opt->csv.good_confidence,
                  "a 0-100 confidence/quality column: good at or above this")
      ->check(CLI::Range(0.0, 100.0));
  cmd->add_option("--from", opt->csv.from,
                  "first time to read (ISO 8601 or epoch s; local with --time-zone)");
  cmd->add_option("--to", opt->csv.to, "last time to read");
  cmd->footer(
      "Exports as PI, IP.21, PHD, DeltaV/Experion and European Excel write them, and the "
      "options for each: host/import/README.md, \"Your historian -> the options\".");
  cmd->callback([opt] { run(*opt); });
}

}  // namespace excite::host::cli
