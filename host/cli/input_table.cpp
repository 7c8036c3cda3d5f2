// SPDX-License-Identifier: MIT
#include "host/cli/input_table.hpp"

#include "host/cli/json_util.hpp"
#include "host/cli/text_table.hpp"

namespace excite::host::cli {
namespace {

std::vector<std::string> cells(const std::string& name, const ChannelMeasures& c) {
  return {name,       num(c.crest_factor), num(c.pips), num(c.peak_factor),
          num(c.phi), num(c.phi_smooth),   num(c.rms),  num(c.min),
          num(c.max), num(c.max_step)};
}

nlohmann::json channel_json(const ChannelMeasures& c) {
  return {{"cf", to_json(c.crest_factor)},
          {"pips", to_json(c.pips)},
          {"pf", to_json(c.peak_factor)},
          {"phi", to_json(c.phi)},
          {"phi_smooth", to_json(c.phi_smooth)},
          {"rms", to_json(c.rms)},
          {"min", to_json(c.min)},
          {"max", to_json(c.max)},
          {"max_step", to_json(c.max_step)}};
}

}  // namespace

void print_input_measures(std::ostream& out, const InputMeasures& m,
                          const std::vector<std::string>& channel_names) {
  TextTable table(
      {"channel", "CF", "PIPS %", "PF", "Phi %", "Phi_i", "RMS", "min", "max", "max|du|"});
  for (std::size_t c = 0; c < m.channels.size(); ++c)
    table.add_row(cells(channel_names.at(c), m.channels[c]));
  table.add_row(cells("average", m.average));
  table.print(out);
}

nlohmann::json input_measures_json(const InputMeasures& m,
                                   const std::vector<std::string>& channel_names) {
  nlohmann::json channels = nlohmann::json::array();
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    nlohmann::json j = channel_json(m.channels[c]);
    j["name"] = channel_names.at(c);
    channels.push_back(j);
  }
  return {{"channels", channels}, {"average", channel_json(m.average)}};
}

}  // namespace excite::host::cli
