// SPDX-License-Identifier: MIT
#pragma once
// Assertions on the order of Modbus requests on the wire (recording_proxy.hpp).

#include <gtest/gtest.h>

#include <cstddef>
#include <cstdio>
#include <map>
#include <vector>

#include "recording_proxy.hpp"

namespace excite::test {

/// Reconnect hygiene seen on the wire: the stall cost the gateway its connection (more than
/// one connection), the one it dropped ends with the request that got no reply, and on every
/// connection no write (FC 6 or 16) is sent before a read (FC 3 or 4) on that connection has
/// been answered successfully (not an exception). Only frames recorded by the proxy count.
inline void expect_read_before_write_on_every_connection(
    const std::vector<RecordingProxy::Frame>& frames) {
  std::map<int, bool> read_ok;    // per connection: a read has been answered
  std::map<int, int> unanswered;  // per connection: requests without a reply yet
  std::map<int, std::size_t> writes;
  for (std::size_t n = 0; n < frames.size(); ++n) {
    const RecordingProxy::Frame& f = frames[n];
    read_ok.emplace(f.connection, false);
    if (f.request) {
      ++unanswered[f.connection];
      if (f.function == 16 || f.function == 6) {
        ++writes[f.connection];
        EXPECT_TRUE(read_ok[f.connection])
            << "frame " << n << ": FC" << int{f.function} << " on connection " << f.connection
            << " before any successful read on it";
      }
    } else {
      --unanswered[f.connection];
      if (f.function == 3 || f.function == 4) read_ok[f.connection] = true;
    }
  }
  EXPECT_GE(read_ok.size(), 2U) << "the stall did not cost the connection: nothing reconnected";
  std::size_t total_writes = 0;
  for (const auto& [c, w] : writes) total_writes += w;
  EXPECT_GT(total_writes, 100U) << "the run wrote almost nothing through the proxy";
  std::size_t left_unanswered = 0;
  for (const auto& [c, u] : unanswered) left_unanswered += static_cast<std::size_t>(u);
  EXPECT_GE(left_unanswered, 1U) << "no exchange was lost to the stall";
  std::printf("[ measured ] wire: %zu frames on %zu connections, %zu writes, %zu unanswered\n",
              frames.size(), read_ok.size(), total_writes, left_unanswered);
}

}  // namespace excite::test
