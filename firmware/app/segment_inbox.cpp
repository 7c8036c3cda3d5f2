// SPDX-License-Identifier: MIT
#include "firmware/app/segment_inbox.hpp"

#include <sys/stat.h>

#include <chrono>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "firmware/app/distortion_check.hpp"
#include "firmware/app/inbox_files.hpp"
#include "firmware/app/run_identity.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/engine/segment.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::app {

// The checks decode a plan and generate its table: more stack than the other helpers.
constexpr std::size_t kInboxStack = 1024 * 1024;

SegmentInbox::SegmentInbox(SegmentInboxSetup setup) : setup_(std::move(setup)) {}

SegmentInbox::~SegmentInbox() {
  stop();
}

void SegmentInbox::start(int interval_ms) {
  stopping_ = false;
  started_ = thread_.start(
      [this, interval_ms] {
        while (!stopping_.load()) {
          poll_once();
          std::this_thread::sleep_for(std::chrono::milliseconds(interval_ms));
        }
      },
      kInboxStack);
}

void SegmentInbox::stop() {
  if (!started_) return;
  started_ = false;
  stopping_ = true;
  thread_.join();
}

void SegmentInbox::say(const std::string& line) {
  if (setup_.events == nullptr) return;
  std::fprintf(setup_.events, "excite-gateway: %s\n", line.c_str());
  std::fflush(setup_.events);
}

std::string SegmentInbox::check(std::span<const std::uint8_t> bytes, std::uint32_t id,
                                plan::Plan& next, signal::TableView& table) {
  const GatewayConfig& config = *setup_.config;
  const auto channels = static_cast<std::uint32_t>(config.setpoints.size());
  const std::span<double> storage = setup_.buffers[id % 2];
  if (auto s =
          engine::load_plan(bytes, channels, storage.size(), next, streamed_excitation(config));
      !s)
    return s.message();
  if (auto s = engine::check_segment(*setup_.running, next); !s) return s.message();
  std::vector<double> scratch(signal::scratch_size(next.recipe));
  if (auto s = engine::make_table(next, storage, scratch, table); !s) return s.message();
  const std::span<const double> baseline(setup_.baseline.data(), channels);
  if (auto s = engine::check_segment_table(setup_.engine_config, baseline, table); !s) {
    return s.message();
  }
  const DistortionVerdict d =
      check_distortion(config, setup_.engine_config, table, baseline, setup_.allow_distortion);
  return d.refusal;
}

void SegmentInbox::refuse(const std::string& path, const std::string& why, std::uint32_t running) {
  std::string error;
  const std::string aside = rename_aside(path, setup_.dir, "next.plan.refused", "", error);
  ++refused_;
  say("segment refused: " + path + ": " + why + "; the running segment " + std::to_string(running) +
      " continues (" +
      (aside.empty() ? "it could not be moved aside: " + error : "the file is now " + aside) +
      "; drop a segment atomically: write it to a temporary name in " + setup_.dir +
      " and rename it to next.plan)");
}

std::string SegmentInbox::set_aside_waiting(const std::string& dir, bool take, std::FILE* events) {
  const std::string path = dir + "/next.plan";
  struct stat st {};
  if (take || lstat(path.c_str(), &st) != 0) return "";
  std::string error;
  const std::string aside = rename_aside(path, dir, "next.plan.refused", "", error);
  const std::string line =
      "segment refused: " + path +
      ": present when the gateway started, expected a segment written during this run (an "
      "earlier run's decision; --take-waiting-segment takes it) (" +
      (aside.empty() ? "it could not be moved aside: " + error : "the file is now " + aside) + ")";
  if (events != nullptr) std::fprintf(events, "excite-gateway: %s\n", line.c_str());
  return aside.empty() ? line : "";
}

bool SegmentInbox::poll_once() {
  const std::string path = setup_.dir + "/next.plan";
  struct stat named {};
  if (lstat(path.c_str(), &named) != 0) return false;  // nothing dropped
  // One segment in flight: the next waits until the engine has switched to the last one.
  const std::uint32_t published = handoff_.published.load(std::memory_order_acquire);
  if (handoff_.running.load(std::memory_order_acquire) != published) return false;
  if (handoff_.stage_refused.load()) return false;  // the run is ending: nothing more is taken
  const std::uint32_t id = published + 1;

  // The folder is an input from outside: no link followed, no blocking open, a regular file
  // of this user's, no larger than the largest plan (inbox_files.hpp).
  const SegmentFile file = read_segment_file(path, plan::max_encoded_size());
  if (!file.present) return false;
  auto next = std::make_unique<plan::Plan>();
  signal::TableView table;
  std::string why = file.refusal;
  if (why.empty()) why = check(file.bytes, id, *next, table);
  if (!why.empty()) {
    if (file.refusal.empty() && file.bytes.size() < plan::max_encoded_size()) {
      why += " (" + std::to_string(file.bytes.size()) + " bytes read: a file still being written?)";
    }
    refuse(path, why, published);
    return true;
  }
  const std::string_view provenance = plan::text_of(next->meta.provenance);
  const std::string& from = setup_.config->segment_preapproved_from;
  const bool preapproval = !from.empty() && provenance.find(from) != std::string_view::npos;
  // The run a segment was decided for (run_identity.hpp): another run's is refused; only
  // this run's may be pre-approved.
  const std::optional<std::string> run = run_named_in(provenance);
  if (!setup_.run_id.empty() && run && *run != setup_.run_id) {
    refuse(path,
           "segment run = " + *run + ", expected this run's " + setup_.run_id +
               " (a segment decided for another gateway run)",
           published);
    return true;
  }
  const bool approved = preapproval && (setup_.run_id.empty() || run.has_value());
  const std::string not_preapproved =
      preapproval && !approved ? "; not pre-approved: its provenance names no run, expected \"" +
                                     run_tag(setup_.run_id) + "\""
                               : "";
  // Kept under a name nobody holds: an earlier run's segment-N.plan is never overwritten.
  std::string error;
  const std::string kept =
      rename_aside(path, setup_.dir, "segment-" + std::to_string(id), ".plan", error);
  if (kept.empty()) {
    refuse(path,
           "file = not movable to segment-" + std::to_string(id) + ".plan (" + error +
               "), expected a segment the gateway can keep as the record",
           published);
    return true;
  }
  handoff_.table = table;
  handoff_.approved = approved;
  handoff_.published.store(id, std::memory_order_release);
  ++staged_;
  say("segment " + std::to_string(id) + " staged: " + setup_.dir + "/" + kept + " (" +
      std::string(plan::text_of(next->meta.design_name)) + ", " + std::to_string(table.samples) +
      " rows, provenance \"" + std::string(provenance) + "\"); " +
      (approved
           ? "pre-approved (segments.preapproved_from = \"" + from + "\")"
           : "waiting for approval (stdin `approve`, command register 5" + not_preapproved + ")"));
  return true;
}

}  // namespace excite::app
