// SPDX-License-Identifier: MIT
#include "firmware/app/segment_inbox.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <thread>
#include <vector>

#include "firmware/app/distortion_check.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/engine/segment.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/signal/generate.hpp"

namespace excite::app {

namespace fs = std::filesystem;

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
  if (auto s = engine::load_plan(bytes, channels, storage.size(), next); !s) return s.message();
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

bool SegmentInbox::poll_once() {
  const fs::path inbox = fs::path(setup_.dir) / "next.plan";
  std::error_code ec;
  if (!fs::is_regular_file(inbox, ec)) return false;
  // One segment in flight: the next waits until the engine has switched to the last one.
  const std::uint32_t published = handoff_.published.load(std::memory_order_acquire);
  if (handoff_.running.load(std::memory_order_acquire) != published) return false;
  if (handoff_.stage_refused.load()) return false;  // the run is ending: nothing more is taken
  const std::uint32_t id = published + 1;

  // No file larger than the largest plan is read (the folder is an input from outside).
  const std::uintmax_t size = fs::file_size(inbox, ec);
  std::string why;
  std::vector<std::uint8_t> bytes;
  if (ec) {
    why = "cannot read the file (" + ec.message() + ")";
  } else if (size > plan::max_encoded_size()) {
    why = "file size = " + std::to_string(size) + " bytes, expected at most " +
          std::to_string(plan::max_encoded_size()) + " (the largest plan)";
  } else {
    std::ifstream in(inbox, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) why = "cannot read the file";
  }
  auto next = std::make_unique<plan::Plan>();
  signal::TableView table;
  if (why.empty()) why = check(bytes, id, *next, table);
  if (!why.empty()) {
    fs::rename(inbox, fs::path(inbox).concat(".refused"), ec);
    ++refused_;
    say("segment refused: " + inbox.string() + ": " + why + "; the running segment " +
        std::to_string(published) + " continues (the file is now next.plan.refused)");
    return true;
  }
  const std::string_view provenance = plan::text_of(next->meta.provenance);
  const std::string& from = setup_.config->segment_preapproved_from;
  const bool approved = !from.empty() && provenance.find(from) != std::string_view::npos;
  handoff_.table = table;
  handoff_.approved = approved;
  handoff_.published.store(id, std::memory_order_release);
  ++staged_;
  const fs::path kept = fs::path(setup_.dir) / ("segment-" + std::to_string(id) + ".plan");
  fs::rename(inbox, kept, ec);
  say("segment " + std::to_string(id) + " staged: " + kept.string() + " (" +
      std::string(plan::text_of(next->meta.design_name)) + ", " + std::to_string(table.samples) +
      " rows, provenance \"" + std::string(provenance) + "\"); " +
      (approved ? "pre-approved (segments.preapproved_from = \"" + from + "\")"
                : std::string("waiting for approval (stdin `approve`, command register 5)")));
  return true;
}

}  // namespace excite::app
