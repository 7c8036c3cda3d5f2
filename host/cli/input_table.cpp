// SPDX-License-Identifier: MIT
#include "host/cli/input_table.hpp"

#include <cmath>

#include "host/export/json_util.hpp"
#include "host/output/text_table.hpp"

namespace excite::host::cli {
namespace {

std::vector<std::string> cells(const std::string& name, const ChannelMeasures& c,
                               bool with_continuous, double cf_continuous) {
  std::vector<std::string> row{name, num(c.crest_factor)};
  if (with_continuous) row.push_back(num(cf_continuous));
  for (const double v :
       {c.pips, c.peak_factor, c.phi, c.phi_smooth, c.rms, c.min, c.max, c.max_step}) {
    row.push_back(num(v));
  }
  return row;
}

nlohmann::json channel_json(const ChannelMeasures& c, double cf_continuous) {
  return {{"cf", to_json(c.crest_factor)}, {"cf_continuous", to_json(cf_continuous)},
          {"pips", to_json(c.pips)},       {"pf", to_json(c.peak_factor)},
          {"phi", to_json(c.phi)},         {"phi_smooth", to_json(c.phi_smooth)},
          {"rms", to_json(c.rms)},         {"min", to_json(c.min)},
          {"max", to_json(c.max)},         {"max_step", to_json(c.max_step)}};
}

// Average of the finite entries; NaN when there are none.
double finite_mean(const std::vector<double>& values) {
  double sum = 0.0;
  int count = 0;
  for (const double v : values) {
    if (std::isfinite(v)) {
      sum += v;
      ++count;
    }
  }
  return count > 0 ? sum / count : std::nan("");
}

}  // namespace

void print_input_measures(std::ostream& out, const InputMeasures& m,
                          const std::vector<std::string>& channel_names,
                          const std::vector<double>& cf_continuous) {
  const double cf_continuous_avg = finite_mean(cf_continuous);
  const bool with_continuous = std::isfinite(cf_continuous_avg);
  std::vector<std::string> header{"channel", "CF"};
  if (with_continuous) header.emplace_back("CF cont.");
  for (const char* h : {"PIPS %", "PF", "Phi %", "Phi_i", "RMS", "min", "max", "max|du|"})
    header.emplace_back(h);
  TextTable table(header);
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    table.add_row(cells(channel_names.at(c), m.channels[c], with_continuous, cf_continuous.at(c)));
  }
  table.add_row(cells("average", m.average, with_continuous, cf_continuous_avg));
  table.print(out);
}

nlohmann::json input_measures_json(const InputMeasures& m,
                                   const std::vector<std::string>& channel_names,
                                   const std::vector<double>& cf_continuous) {
  nlohmann::json channels = nlohmann::json::array();
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    nlohmann::json j = channel_json(m.channels[c], cf_continuous.at(c));
    j["name"] = channel_names.at(c);
    channels.push_back(j);
  }
  return {{"channels", channels}, {"average", channel_json(m.average, finite_mean(cf_continuous))}};
}

}  // namespace excite::host::cli
