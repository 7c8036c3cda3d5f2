// SPDX-License-Identifier: MIT
#include "host/import/historian_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "base/config/document.hpp"
#include "host/import/csv_text.hpp"
#include "host/import/number_text.hpp"
#include "host/import/time_zone.hpp"
#include "host/import/timestamp.hpp"

namespace excite::host::historian {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::size_t kBadExamples = 3;

bool is_units_label(const std::string& cell) {
  const std::string c = lower(trim(cell));
  return c == "units" || c == "unit" || c == "eu" || c == "eng units" || c == "engineering units" ||
         c == "uom";
}

// Where one tag's cells are in a row.
struct TagColumns {
  std::size_t value = 0;
  std::size_t time = 0;
  std::ptrdiff_t quality = -1;
  bool confidence = false;
};

enum class Magnitude { relative, s, ms, us, beyond };

Magnitude magnitude_of(double v) {
  const double a = std::fabs(v);
  if (a < 1e8) return Magnitude::relative;  // seconds from some start (before 1973 as epoch)
  if (a < 1e11) return Magnitude::s;        // 1973 … 5138
  if (a < 1e14) return Magnitude::ms;
  if (a < 1e17) return Magnitude::us;
  return Magnitude::beyond;
}

const char* unit_name(Magnitude m) {
  switch (m) {
    case Magnitude::ms:
      return "ms";
    case Magnitude::us:
      return "us";
    default:
      return "s";
  }
}

double scale_of(Magnitude m) {
  return m == Magnitude::ms ? 1e3 : (m == Magnitude::us ? 1e6 : 1.0);
}

Magnitude magnitude_of(Epoch e) {
  switch (e) {
    case Epoch::ms:
      return Magnitude::ms;
    case Epoch::us:
      return Magnitude::us;
    default:
      return Magnitude::s;
  }
}

class Reader {
 public:
  Reader(std::istream& in, const std::string& file, const std::vector<std::string>& tags,
         const CsvOptions& o)
      : lines_(in, file, o.max_line_bytes), file_(file), tags_(tags), o_(o) {
    if (!o.time_zone.empty()) zone_ = std::make_unique<TimeZone>(o.time_zone);
    if (!o.time_format.empty()) {
      const std::string problem = check_time_format(o.time_format);
      if (!problem.empty()) {
        throw std::invalid_argument("--time-format = " + quote_cell(o.time_format) + ", expected " +
                                    "a strftime-style format (host/import/README.md): " + problem);
      }
    }
  }

  HistorianData read();

 private:
  std::string at(std::size_t line) const { return file_ + ":" + std::to_string(line) + ": "; }
  void read_header();
  void resolve_wide();
  // --long: the header checked (TAG,TIME,VALUE[,QUALITY], names, not a sample); each tag's
  // index by its name.
  std::unordered_map<std::string, std::size_t> resolve_long();
  std::size_t resolve_tag(const std::string& tag) const;
  std::ptrdiff_t quality_column(std::size_t value_col) const;
  void read_header_rows();
  std::optional<double> window_bound(const std::string& text, const char* option);
  double time_of(const std::string& text, std::size_t line, const std::string& field);
  void add(std::size_t g, double t, const std::string& time_text, const std::string& value,
           const std::string* quality, std::size_t line, const std::string& time_field);
  void finish();

  LineReader lines_;
  const std::string& file_;
  const std::vector<std::string>& tags_;
  const CsvOptions& o_;
  std::unique_ptr<TimeZone> zone_;
  std::vector<std::string> header_;
  std::size_t header_line_ = 0;
  std::vector<TagColumns> cols_;
  bool per_tag_ = false;  // each tag has its own time column
  std::optional<double> from_s_, to_s_;
  // The zone state of the first timestamp read, and its line (mixed zoned/naive refused).
  std::optional<bool> first_zoned_;
  std::size_t first_zoned_line_ = 0;
  std::vector<double> last_time_;
  std::vector<std::size_t> last_line_;
  std::vector<std::string> last_text_;
  std::vector<std::size_t> quality_bad_;  // per tag: numbers made bad by the quality column
  std::vector<BadCell> first_quality_bad_;
  HistorianData d_;
};

// The encoding of a first line that is not UTF-8 or ASCII text, by its byte order mark or
// its zero bytes (UTF-16 has one in every pair for ASCII text, UTF-32 three in four); empty
// when it reads as 8-bit text.
std::string wide_encoding(const std::string& line) {
  if (line.rfind(std::string("\xFF\xFE\0\0", 4), 0) == 0)
    return "UTF-32LE (byte order mark FF FE 00 00)";
  if (line.rfind(std::string("\0\0\xFE\xFF", 4), 0) == 0)
    return "UTF-32BE (byte order mark 00 00 FE FF)";
  if (line.rfind("\xFF\xFE", 0) == 0) return "UTF-16LE (byte order mark FF FE)";
  if (line.rfind("\xFE\xFF", 0) == 0) return "UTF-16BE (byte order mark FE FF)";
  const auto zeros = static_cast<std::size_t>(std::count(line.begin(), line.end(), '\0'));
  if (line.size() >= 4 && zeros * 4 >= line.size() * 3 - 3) return "UTF-32 (no byte order mark)";
  if (line.size() >= 2 && zeros * 2 >= line.size() - 1) return "UTF-16 (no byte order mark)";
  return {};
}

void Reader::read_header() {
  std::string line;
  while (lines_.next(line)) {
    if (lines_.line_number() == 1) {
      const std::string encoding = wide_encoding(line);
      if (!encoding.empty()) {
        throw std::invalid_argument(
            at(1) + "encoding = " + encoding +
            ", expected UTF-8 or ASCII text: save the export as UTF-8 (Excel: CSV UTF-8), or "
            "convert it (iconv -f " +
            encoding.substr(0, encoding.find(' ')) + " -t UTF-8)");
      }
    }
    // Excel's "CSV UTF-8" starts the file with a byte order mark.
    if (lines_.line_number() == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    header_ = split(t, o_.delimiter);
    header_line_ = lines_.line_number();
    return;
  }
  throw std::invalid_argument(file_ +
                              ": no header row, expected a row of column names "
                              "(timestamp, then one column per tag)");
}

std::size_t Reader::resolve_tag(const std::string& tag) const {
  const auto columns_named = [&](const std::string& name) {
    std::vector<std::size_t> out;
    for (std::size_t c = 0; c < header_.size(); ++c) {
      if (header_[c] == name) out.push_back(c);
    }
    return out;
  };
  std::vector<std::size_t> cols = columns_named(tag);
  if (cols.size() > 1) {
    std::string list;
    for (std::size_t i = 0; i < cols.size() && i < 20; ++i) {
      list += (i == 0 ? "" : ", ") + std::to_string(cols[i] + 1);
    }
    throw std::invalid_argument(at(header_line_) + "tag = " + quote_cell(tag) + " (columns " +
                                list + "), expected a unique column name; address one as '" + tag +
                                "#1' … '" + tag + "#" + std::to_string(cols.size()) +
                                "' (the n-th column of that name) in --mv, --cv or --map");
  }
  if (cols.size() == 1) return cols[0];
  const std::size_t hash = tag.rfind('#');
  if (hash != std::string::npos && hash > 0) {
    std::size_t n = 0;
    const char* b = tag.data() + hash + 1;
    const char* e = tag.data() + tag.size();
    const auto [end, ec] = std::from_chars(b, e, n);
    if (ec == std::errc() && end == e) {
      cols = columns_named(tag.substr(0, hash));
      if (n >= 1 && n <= cols.size()) return cols[n - 1];
    }
  }
  throw std::invalid_argument(at(header_line_) + "tag = " + quote_cell(tag) +
                              ", expected a column of the header: " + column_list(header_));
}

std::ptrdiff_t Reader::quality_column(std::size_t value_col) const {
  static constexpr const char* kSuffixes[] = {".quality",    "_quality",    ":quality",
                                              " quality",    ".confidence", "_confidence",
                                              ":confidence", " confidence"};
  const std::string base = lower(header_[value_col]);
  std::ptrdiff_t best = -1;
  for (std::size_t c = 0; c < header_.size(); ++c) {
    const std::string name = lower(header_[c]);
    bool match = false;
    for (const char* s : kSuffixes) match = match || name == base + s;
    if (!match) continue;
    // The nearest such column to the right of the value; else the first.
    if (best < 0 || (c > value_col && static_cast<std::size_t>(best) < value_col)) {
      best = static_cast<std::ptrdiff_t>(c);
    }
  }
  return best;
}

void Reader::resolve_wide() {
  std::string time_name = o_.time_column.empty() ? header_.front() : o_.time_column;
  std::vector<std::size_t> time_cols;
  for (std::size_t c = 0; c < header_.size(); ++c) {
    if (header_[c] == time_name) time_cols.push_back(c);
  }
  if (time_cols.empty()) {
    throw std::invalid_argument(at(header_line_) + "--time-column = " + quote_cell(time_name) +
                                ", expected a column of the header: " + column_list(header_));
  }
  per_tag_ = time_cols.size() > 1 || o_.time_column_per_tag;
  for (const auto& tag : tags_) {
    TagColumns tc;
    tc.value = resolve_tag(tag);
    if (o_.time_column_per_tag) {
      if (tc.value % 2 == 0) {
        throw std::invalid_argument(at(header_line_) + "tag = " + quote_cell(tag) + " (column " +
                                    std::to_string(tc.value + 1) +
                                    "), expected a value column: with --time-column-per-tag the "
                                    "columns are TIME,VALUE pairs, values in columns 2, 4, …");
      }
      tc.time = tc.value - 1;
    } else {
      bool found = false;
      for (const std::size_t t : time_cols) {
        if (t < tc.value) {
          tc.time = t;
          found = true;
        }
      }
      if (!found) {
        throw std::invalid_argument(at(header_line_) + "tag = " + quote_cell(tag) + " (column " +
                                    std::to_string(tc.value + 1) +
                                    "), expected a value column after a time column " +
                                    quote_cell(time_name));
      }
    }
    tc.quality = quality_column(tc.value);
    if (tc.quality >= 0) {
      const std::string& qname = header_[static_cast<std::size_t>(tc.quality)];
      tc.confidence = lower(qname).find("confidence") != std::string::npos;
      if (tc.confidence && std::isnan(o_.good_confidence)) {
        throw std::invalid_argument(at(header_line_) + "column " + quote_cell(qname) +
                                    " = a 0–100 confidence, expected --good-confidence N (the "
                                    "least confidence that is good)");
      }
    }
    cols_.push_back(tc);
  }
}

void Reader::read_header_rows() {
  std::string line;
  for (std::size_t r = 0; r < o_.header_rows; ++r) {
    if (!lines_.next(line)) {
      throw std::invalid_argument(file_ + ":" + std::to_string(header_line_) +
                                  ": --header-rows = " + std::to_string(o_.header_rows) +
                                  ", expected that many rows after the header; the file ends");
    }
    const std::vector<std::string> f = split(line, o_.delimiter);
    if (o_.long_format || f.empty() || !is_units_label(f.front())) continue;
    for (std::size_t g = 0; g < tags_.size(); ++g) {
      if (cols_[g].value < f.size()) d_.units[g] = trim(f[cols_[g].value]);
    }
    d_.units_line = lines_.line_number();
  }
}

std::optional<double> Reader::window_bound(const std::string& text, const char* option) {
  if (text.empty()) return std::nullopt;
  const std::optional<Timestamp> t = parse_iso_or_epoch(text);
  if (!t) {
    throw std::invalid_argument(std::string(option) + " = " + quote_cell(text) +
                                ", expected ISO 8601 (2026-03-01T08:00:00, optional Z or "
                                "±HH:MM) or epoch seconds");
  }
  if (t->zoned || !zone_) return t->seconds;
  const TimeZone::Result r = zone_->to_utc(t->seconds);
  if (r.status == TimeZone::Local::skipped) {
    throw std::invalid_argument(std::string(option) + " = " + quote_cell(text) +
                                ", expected a local time of " + zone_->name() +
                                " (this one is skipped by a daylight-saving change)");
  }
  return r.utc_s;
}

double Reader::time_of(const std::string& text, std::size_t line, const std::string& field) {
  const std::string here = at(line) + field + " = " + quote_cell(text) + ", expected ";
  std::optional<Timestamp> ts;
  bool numeric = false;
  if (!o_.time_format.empty()) {
    ts = parse_formatted(text, o_.time_format);
    if (!ts) throw std::invalid_argument(here + "a time of the form " + o_.time_format);
  } else {
    ts = parse_iso_or_epoch(text);
    if (!ts) {
      throw std::invalid_argument(here +
                                  "ISO 8601 (2026-03-01T08:00:00, optional Z or ±HH:MM) or "
                                  "epoch seconds (--time-format for other forms)");
    }
    numeric = !(text.size() >= 10 && text[4] == '-');
  }
  if (numeric) {
    const Magnitude m = magnitude_of(ts->seconds);
    if (m == Magnitude::beyond) {
      throw std::invalid_argument(here + "epoch seconds, ms or us (below 1e17)");
    }
    if (o_.epoch == Epoch::automatic && m != Magnitude::relative && m != Magnitude::s) {
      throw std::invalid_argument(here + "epoch seconds; its magnitude reads as " + unit_name(m) +
                                  " since 1970 (" + format_utc(ts->seconds / scale_of(m)) +
                                  "): give --epoch " + unit_name(m));
    }
    if (o_.epoch != Epoch::automatic && m != Magnitude::relative && m != magnitude_of(o_.epoch)) {
      throw std::invalid_argument(here + "epoch " + unit_name(magnitude_of(o_.epoch)) +
                                  " (--epoch); its magnitude reads as " + unit_name(m) +
                                  " since 1970 (" + format_utc(ts->seconds / scale_of(m)) + ")");
    }
    ts->seconds /= scale_of(o_.epoch == Epoch::automatic ? Magnitude::s : magnitude_of(o_.epoch));
  }
  if (!first_zoned_) {
    first_zoned_ = ts->zoned;
    first_zoned_line_ = line;
  } else if (*first_zoned_ != ts->zoned) {
    throw std::invalid_argument(
        here + (ts->zoned ? "a time without a zone" : "a time with a zone (Z, ±HH:MM or epoch)") +
        " as on line " + std::to_string(first_zoned_line_) +
        " (zoned and naive timestamps are not mixed)");
  }
  if (!zone_) return ts->seconds;
  if (ts->zoned) {
    throw std::invalid_argument(here + "a local time without a zone (--time-zone " + zone_->name() +
                                " converts local times)");
  }
  const TimeZone::Result r = zone_->to_utc(ts->seconds);
  if (r.status == TimeZone::Local::skipped) {
    throw std::invalid_argument(here + "a local time of " + zone_->name() +
                                "; the daylight-saving change skips it");
  }
  if (r.status == TimeZone::Local::ambiguous) {
    throw std::invalid_argument(here + "an unambiguous local time of " + zone_->name() +
                                "; the daylight-saving change repeats it (" + format_utc(r.utc_s) +
                                " or " + format_utc(r.later_s) +
                                "): export in UTC or with offsets");
  }
  return r.utc_s;
}

void Reader::add(std::size_t g, double t, const std::string& time_text, const std::string& value,
                 const std::string* quality, std::size_t line, const std::string& time_field) {
  if (!last_text_[g].empty() && !(t > last_time_[g])) {
    throw std::invalid_argument(at(line) + time_field + " = " + quote_cell(time_text) +
                                ", expected a time after " + quote_cell(last_text_[g]) + " (line " +
                                std::to_string(last_line_[g]) + ") of tag '" + tags_[g] +
                                "': timestamps strictly increasing");
  }
  last_time_[g] = t;
  last_line_[g] = line;
  last_text_[g] = time_text.empty() ? std::string(" ") : time_text;
  if ((from_s_ && t < *from_s_) || (to_s_ && t > *to_s_)) return;
  TagSeries& s = d_.series[g];
  if (s.time_s.size() >= o_.max_samples) {
    throw std::invalid_argument(at(line) + "tag '" + tags_[g] + "' = more than " +
                                std::to_string(o_.max_samples) + " samples, expected at most " +
                                std::to_string(o_.max_samples) +
                                " (give --from/--to, a time window)");
  }
  const std::optional<double> parsed = parse_number(value, o_.decimal_comma);
  double v = parsed ? *parsed : kNaN;
  if (parsed && std::fabs(v) > o_.max_value) {
    throw std::invalid_argument(at(line) + tags_[g] + " = " + quote_cell(value) +
                                ", expected |value| <= " + config::format_number(o_.max_value) +
                                " (so that the run log's values and deviations stay within its "
                                "limit)");
  }
  if (!parsed && d_.bad_examples[g].size() < kBadExamples) {
    d_.bad_examples[g].push_back({line, value});
  }
  if (quality != nullptr && parsed) {
    bool good = false;
    if (!std::isnan(o_.good_confidence)) {
      const std::optional<double> c = parse_number(*quality, o_.decimal_comma);
      good = c && *c >= o_.good_confidence;
    } else if (lower(*quality) == "good") {
      good = true;
    } else {
      unsigned q = 0;
      const auto [end, ec] = std::from_chars(quality->data(), quality->data() + quality->size(), q);
      good = ec == std::errc() && end == quality->data() + quality->size() && q <= 255U &&
             (q & 0xC0U) == 0xC0U;
    }
    if (!good) {
      v = kNaN;
      if (quality_bad_[g]++ == 0) first_quality_bad_[g] = {line, *quality};
    }
  }
  if (std::isnan(v)) ++d_.bad_cells[g];
  s.time_s.push_back(t);
  s.values.push_back(v);
  s.line.push_back(line);
}

void Reader::finish() {
  for (std::size_t g = 0; g < tags_.size(); ++g) {
    const TagSeries& s = d_.series[g];
    if (s.time_s.empty()) {
      throw std::invalid_argument(
          at(header_line_) + "tag '" + tags_[g] + "' = no samples" +
          (from_s_ || to_s_ ? " in the --from/--to window" : std::string()) +
          ", expected at least one row with its value");
    }
    if (quality_bad_[g] == s.time_s.size() && std::isnan(o_.good_confidence)) {
      throw std::invalid_argument(
          at(first_quality_bad_[g].line) + "quality of " + tags_[g] + " = " +
          quote_cell(first_quality_bad_[g].text) +
          ", expected 'good' or an OPC quality code 192–255: it makes every value of the tag "
          "bad; a 0–100 confidence (PHD)? give --good-confidence N");
    }
  }
}

std::unordered_map<std::string, std::size_t> Reader::resolve_long() {
  const std::size_t n_tags = tags_.size();
  std::unordered_map<std::string, std::size_t> long_tag;
  if (header_.size() < 3 || header_.size() > 4) {
    throw std::invalid_argument(at(header_line_) + "header = " + column_list(header_) +
                                ", expected TAG,TIME,VALUE[,QUALITY] (--long)");
  }
  // A long export without its header row: the first sample is not column names.
  if (parse_number(trim(header_[2]), o_.decimal_comma)) {
    throw std::invalid_argument(
        at(header_line_) + "header = " + column_list(header_) +
        ", expected column names TAG,TIME,VALUE[,QUALITY] (--long): this row reads as a "
        "sample (its VALUE " +
        quote_cell(header_[2]) + " is a number); export with the header row, or add one");
  }
  for (std::size_t g = 0; g < n_tags; ++g) long_tag.emplace(tags_[g], g);
  if (header_.size() == 4) {
    const bool confidence = lower(header_[3]).find("confidence") != std::string::npos;
    if (confidence && std::isnan(o_.good_confidence)) {
      throw std::invalid_argument(at(header_line_) + "column " + quote_cell(header_[3]) +
                                  " = a 0–100 confidence, expected --good-confidence N");
    }
    d_.has_quality.assign(n_tags, true);
  }
  return long_tag;
}

HistorianData Reader::read() {
  read_header();
  const std::size_t n_tags = tags_.size();
  d_.file = file_;
  d_.series.assign(n_tags, {});
  d_.bad_cells.assign(n_tags, 0);
  d_.bad_examples.assign(n_tags, {});
  d_.has_quality.assign(n_tags, false);
  d_.units.assign(n_tags, "");
  last_time_.assign(n_tags, 0.0);
  last_line_.assign(n_tags, 0);
  last_text_.assign(n_tags, "");
  quality_bad_.assign(n_tags, 0);
  first_quality_bad_.assign(n_tags, {});
  std::unordered_map<std::string, std::size_t> long_tag;
  if (o_.long_format) {
    long_tag = resolve_long();
  } else {
    resolve_wide();
    for (std::size_t g = 0; g < n_tags; ++g) d_.has_quality[g] = cols_[g].quality >= 0;
  }
  read_header_rows();
  from_s_ = window_bound(o_.from, "--from");
  to_s_ = window_bound(o_.to, "--to");

  std::vector<std::string> time_names;  // for messages, cut short
  for (const TagColumns& c : cols_) time_names.push_back(short_text(header_[c.time]));
  std::string line;
  std::size_t data_rows = 0;
  std::vector<std::optional<double>> row_time(header_.size());
  while (lines_.next(line)) {
    const std::size_t n = lines_.line_number();
    if (trim(line).empty()) continue;
    const std::vector<std::string> f = split(line, o_.delimiter);
    if (f.size() != header_.size()) {
      throw std::invalid_argument(at(n) + "fields = " + std::to_string(f.size()) + ", expected " +
                                  std::to_string(header_.size()) + " as in the header (line " +
                                  std::to_string(header_line_) + ")");
    }
    ++data_rows;
    if (o_.long_format) {
      const auto it = long_tag.find(f[0]);
      if (it == long_tag.end()) continue;
      const std::string field = short_text(header_[1]);
      const double t = time_of(f[1], n, field);
      add(it->second, t, f[1], f[2], f.size() == 4 ? &f[3] : nullptr, n, field);
      continue;
    }
    for (const TagColumns& c : cols_) row_time[c.time].reset();
    for (std::size_t g = 0; g < n_tags; ++g) {
      const TagColumns& c = cols_[g];
      const std::string& tt = f[c.time];
      const std::string* q = c.quality >= 0 ? &f[static_cast<std::size_t>(c.quality)] : nullptr;
      // Per-tag time columns: a tag without a sample in this row leaves its cells empty.
      if (per_tag_ && tt.empty() && f[c.value].empty() && (q == nullptr || q->empty())) continue;
      if (!row_time[c.time]) row_time[c.time] = time_of(tt, n, time_names[g]);
      add(g, *row_time[c.time], tt, f[c.value], q, n, time_names[g]);
    }
  }
  if (data_rows == 0) {
    throw std::invalid_argument(at(header_line_) +
                                "data rows = 0, expected one row per timestamp after the header");
  }
  finish();
  return std::move(d_);
}

}  // namespace

HistorianData read_historian(std::istream& in, const std::string& file,
                             const std::vector<std::string>& tags, const CsvOptions& options) {
  Reader r(in, file, tags, options);
  return r.read();
}

HistorianData read_historian(const std::string& path, const std::vector<std::string>& tags,
                             const CsvOptions& options) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::invalid_argument(path + ": cannot be opened");
  return read_historian(in, path, tags, options);
}

HistorianData parse_historian(const std::string& text, const std::string& file,
                              const std::vector<std::string>& tags, const CsvOptions& options) {
  std::istringstream in(text);
  return read_historian(in, file, tags, options);
}

}  // namespace excite::host::historian
