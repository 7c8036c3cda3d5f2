// SPDX-License-Identifier: MIT
#include "firmware/engine/load_plan.hpp"

#include "firmware/plan/codec.hpp"
#include "firmware/plan/limits.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::engine {

using signal::Status;
using signal::StatusCode;

Status load_plan(std::span<const std::uint8_t> file, std::uint32_t expected_channels,
                 std::size_t capacity, plan::Plan& out, plan::Excitation streams) {
  if (Status s = plan::decode(file, out, streams != plan::Excitation::open_loop); !s) return s;
  if (out.meta.excitation != plan::Excitation::open_loop && out.meta.excitation != streams) {
    const plan::Excitation found = out.meta.excitation;
    out = plan::Plan{};
    return Status::error(StatusCode::invalid_field,
                         "plan excitation = %s, expected %s or open_loop (what the "
                         "configuration's setpoints are: [closed_loop] offsets)",
                         plan::to_text(found), plan::to_text(streams));
  }
  if (out.recipe.channels != expected_channels) {
    const std::uint32_t found = out.recipe.channels;
    out = plan::Plan{};
    return Status::error(StatusCode::invalid_field,
                         "plan channels = %u, expected %u (the setpoints of the configuration)",
                         found, expected_channels);
  }
  const std::size_t values = std::size_t{out.recipe.channels} * out.recipe.samples;
  if (values > capacity) {
    const std::uint32_t samples = out.recipe.samples;
    const std::uint32_t channels = out.recipe.channels;
    out = plan::Plan{};
    return Status::error(StatusCode::capacity_exceeded,
                         "plan table = %u samples x %u channels = %zu values, expected <= %zu "
                         "(the gateway's table capacity)",
                         samples, channels, values, capacity);
  }
  return {};
}

Status make_table(const plan::Plan& plan, std::span<double> storage, std::span<double> scratch,
                  signal::TableView& table) {
  const std::size_t values = std::size_t{plan.recipe.channels} * plan.recipe.samples;
  if (values > storage.size()) {
    return Status::error(StatusCode::capacity_exceeded,
                         "table storage = %zu values, expected >= %zu", storage.size(), values);
  }
  signal::TableView view{storage.data(), plan.recipe.channels, plan.recipe.samples};
  if (Status s = signal::generate(plan.recipe, view, scratch); !s) return s;
  const plan::LimitCheck check = plan::check_limits(plan, view);
  if (!check.status) return check.status;
  table = view;
  return {};
}

}  // namespace excite::engine
