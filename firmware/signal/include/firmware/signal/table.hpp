// SPDX-License-Identifier: MIT
#pragma once
// A table: the experiment's input deviations, one row per tick (sample-major).
//
//   value of channel c at sample k  =  data[k · channels + c]
//
// so that the gateway hands one contiguous row of `channels` values to the field bus at
// every tick. TableView does not own its storage; the caller keeps it alive.

#include <cstddef>
#include <cstdint>

namespace excite::signal {

struct TableView {
  double* data = nullptr;
  std::uint32_t channels = 0;
  std::uint32_t samples = 0;

  /// Number of values, channels · samples.
  std::size_t size() const { return std::size_t{channels} * samples; }
  double& at(std::uint32_t sample, std::uint32_t channel) const {
    return data[std::size_t{sample} * channels + channel];
  }
  /// The row of sample k: `channels` contiguous values.
  double* row(std::uint32_t sample) const { return data + std::size_t{sample} * channels; }
};

/// Read-only counterpart of TableView (same layout).
struct ConstTableView {
  const double* data = nullptr;
  std::uint32_t channels = 0;
  std::uint32_t samples = 0;

  ConstTableView() = default;
  ConstTableView(const double* d, std::uint32_t c, std::uint32_t s)
      : data(d), channels(c), samples(s) {}
  ConstTableView(TableView t)  // NOLINT(google-explicit-constructor): a view narrows freely
      : data(t.data), channels(t.channels), samples(t.samples) {}

  std::size_t size() const { return std::size_t{channels} * samples; }
  double at(std::uint32_t sample, std::uint32_t channel) const {
    return data[std::size_t{sample} * channels + channel];
  }
};

}  // namespace excite::signal
