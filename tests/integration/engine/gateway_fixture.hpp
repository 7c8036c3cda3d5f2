// SPDX-License-Identifier: MIT
#pragma once
// Closed loop in one process (STYLE.md practice 10): the 4-channel case-study-shaped plan
// (4080 rows, T = 1 min) streamed by the gateway component (firmware/app/gateway.hpp, the
// same one excite-gateway's main() runs) to the alatiqi4x4 plant behind a SimLinkFieldBus,
// on a VirtualClock (hours of plant time in milliseconds), logged by its LogDrain into a
// real CSV file that the run-log reader reads back. Only the bus and the clock differ from
// the field; the configuration is a GatewayConfig as the TOML parser builds it.
//
// Values: [0, 4) outputs, [4, 8) readbacks, 8 heartbeat echo, 9 command register.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/gateway.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/runlog/reader.hpp"
#include "sim/library/library.hpp"
#include "sim/simlink/simlink_field_bus.hpp"
#include "simlink_gateway.hpp"

namespace excite::testing {

// Runs a scripted action after a given tick (fault injection at a known time).
class Script final : public app::TickObserver {
 public:
  void at(std::uint64_t tick, std::function<void()> action) { actions_[tick] = std::move(action); }
  void after_tick(const engine::Engine& engine, std::uint64_t tick) noexcept override {
    states.push_back(engine.state());
    if (auto it = actions_.find(tick); it != actions_.end()) it->second();
  }
  std::vector<engine::State> states;  // reserved by the fixture: no allocation per tick

 private:
  std::map<std::uint64_t, std::function<void()>> actions_;
};

class GatewayLoop : public ::testing::Test {
 protected:
  void SetUp() override {
    plan_file_ = example_plan_file();
    sim::simlink::SimLinkConfig sc;
    sc.input_baseline.assign(kU0, kU0 + kInputs);
    sc.output_baseline.assign(kY0, kY0 + kOutputs);
    sc.command_register = true;
    sc.exchange_time = std::chrono::milliseconds(2);
    bus_ = std::make_unique<sim::simlink::SimLinkFieldBus>(sim::library_plant("alatiqi4x4"), 1.0,
                                                           sc, &clock_);
    config_ = simlink_config({});
    log_path_ = (std::filesystem::temp_directory_path() /
                 ("excite_engine_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv"))
                    .string();
    script_.states.reserve(20000);
  }

  void TearDown() override { std::filesystem::remove(log_path_); }

  // Builds the gateway from config_ and the plan file (stages 1–3) and arms it on the live
  // plant (stage 4); false (with a test failure) when a stage fails.
  bool start_up() {
    config_.log_ring = static_cast<std::uint32_t>(ring_records_);
    gateway_ = std::make_unique<app::Gateway>(config_);
    if (auto e = gateway_->load_plan(plan_file_, "example plan")) {
      ADD_FAILURE() << e->message;
      return false;
    }
    table_ = gateway_->table();
    gateway_->set_observer(&script_);
    gateway_->set_row_delay(row_delay_);
    if (auto e = gateway_->arm(*bus_, clock_)) {
      ADD_FAILURE() << e->message;
      return false;
    }
    return true;
  }

  // Start-up, run log, then runs until safe (or max_ticks_) with the log thread.
  app::RunStats run(engine::Command first = engine::Command::start) {
    if (!start_up()) return {};
    std::FILE* file = std::fopen(log_path_.c_str(), "w");
    EXPECT_NE(file, nullptr);
    if (auto e = gateway_->start_log(file, "excite-gateway (integration test)")) {
      ADD_FAILURE() << e->message;
      std::fclose(file);
      return {};
    }
    if (first != engine::Command::none) commands_.post(first);
    const app::RunStats stats = gateway_->run(commands_, nullptr, max_ticks_);
    EXPECT_EQ(gateway_->finish_log(), runlog::WriteStatus::ok);
    rows_written_ = gateway_->rows_logged();
    std::fclose(file);
    return stats;
  }

  [[nodiscard]] const engine::Engine& engine() const { return gateway_->engine(); }

  runlog::RunLog read_log() {
    runlog::ReadResult r = runlog::read_run_log(log_path_);
    EXPECT_TRUE(r.ok()) << (r.error ? r.error->to_string() : "");
    return r.log;
  }

  static constexpr std::size_t kRing = 8192;
  std::vector<std::uint8_t> plan_file_;
  signal::ConstTableView table_;
  hal::VirtualClock clock_;
  std::unique_ptr<sim::simlink::SimLinkFieldBus> bus_;
  app::GatewayConfig config_;
  std::unique_ptr<app::Gateway> gateway_;
  std::size_t ring_records_ = kRing;
  app::CommandMailbox commands_;
  Script script_;
  std::string log_path_;
  std::chrono::microseconds row_delay_{0};
  std::uint64_t max_ticks_ = 0;
  std::uint64_t rows_written_ = 0;
  double held_[kInputs] = {};
};

}  // namespace excite::testing
