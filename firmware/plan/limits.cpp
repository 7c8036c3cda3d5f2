// SPDX-License-Identifier: MIT
#include "firmware/plan/limits.hpp"

namespace excite::plan {

LimitCheck check_limits(const Plan& plan, signal::ConstTableView table) {
  const signal::Recipe& recipe = plan.recipe;
  if (table.channels != recipe.channels || table.samples != recipe.samples) {
    return {Status::error(StatusCode::invalid_field,
                          "table of %u channels × %u samples, expected the plan's %u × %u",
                          table.channels, table.samples, recipe.channels, recipe.samples)};
  }
  for (std::uint32_t k = 0; k < table.samples; ++k) {
    for (std::uint32_t c = 0; c < table.channels; ++c) {
      const double value = table.at(k, c);
      const ChannelMeta& ch = plan.meta.channels[c];
      if (!(value >= ch.min && value <= ch.max)) {  // NaN fails both
        const std::string_view name = text_of(ch.name);
        return {
            Status::error(StatusCode::limit_violated,
                          "table(sample %u, channel %u \"%.*s\") = %.9g, expected within "
                          "[%.9g, %.9g]",
                          k, c, static_cast<int>(name.size()), name.data(), value, ch.min, ch.max),
            c, k, value};
      }
    }
  }
  return {};
}

}  // namespace excite::plan
