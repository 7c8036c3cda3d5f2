// SPDX-License-Identifier: MIT
#pragma once
// The hand-over of a plan segment from the segment inbox's thread (producer, may allocate) to
// the tick (consumer, allocates nothing): one segment in flight at a time, lock-free.
//
//   inbox: table into the free buffer → table, approved → published.store(id, release)
//   tick:  published.load(acquire) moved → Engine::stage(table, approved); every tick
//          running.store(engine.segment(), release)
//   inbox: the next segment only once running == published (the engine switched to the last
//          one, so the buffer it left is free again)

#include <atomic>
#include <cstdint>

#include "firmware/signal/table.hpp"

namespace excite::app {

struct SegmentHandoff {
  std::atomic<std::uint32_t> published{0};  // id of the last segment staged by the inbox
  std::atomic<std::uint32_t> running{0};    // the engine's segment, stored by the tick
  std::atomic<bool> stage_refused{false};   // the engine refused the last one (the run ends)
  signal::ConstTableView table{};           // the published segment's table …
  bool approved = false;                    // … and whether it is pre-approved
};

}  // namespace excite::app
