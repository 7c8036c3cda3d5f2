// SPDX-License-Identifier: MIT
#pragma once
// Closed loop in one process (STYLE.md practice 10): the 4-channel case-study-shaped plan
// (4080 rows, T = 1 min) streamed by the engine through the Runner to the alatiqi4x4 plant
// behind a SimLinkFieldBus, on a VirtualClock (hours of plant time in milliseconds),
// logged by the LogDrain into a real CSV file that the run-log reader reads back.
//
// Values: [0, 4) outputs, [4, 8) readbacks, 8 heartbeat echo, 9 command register.

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "excite/hal/virtual_clock.hpp"
#include "firmware/app/command_mailbox.hpp"
#include "firmware/app/log_drain.hpp"
#include "firmware/app/runner.hpp"
#include "firmware/engine/engine.hpp"
#include "firmware/engine/load_plan.hpp"
#include "firmware/plan/codec.hpp"
#include "firmware/runlog/reader.hpp"
#include "firmware/signal/generate.hpp"
#include "sim/simlink/simlink_field_bus.hpp"
#include "sim/library/library.hpp"
#include "tests/unit/plan/example_plan.hpp"

namespace excite::testing {

inline constexpr std::uint32_t kInputs = 4;
inline constexpr std::uint32_t kOutputs = 4;
inline constexpr std::uint32_t kEcho = 8;
inline constexpr std::uint32_t kCommand = 9;
inline constexpr double kU0[kInputs] = {50.0, 60.0, 70.0, 80.0};
inline constexpr double kY0[kOutputs] = {0.9, 0.1, 0.5, 0.3};
inline constexpr double kTestBand = 1000.0;  // test limits y0 ± band: never hit by the plan

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
    plan_ = plan::testing::example_plan();
    std::vector<std::uint8_t> bytes(plan::max_encoded_size());
    const plan::EncodeResult encoded = plan::encode(*plan_, bytes);
    ASSERT_TRUE(encoded.status);
    bytes.resize(encoded.size);
    loaded_ = std::make_unique<plan::Plan>();
    ASSERT_TRUE(engine::load_plan(bytes, kInputs, signal::kTableCapacity, *loaded_));
    storage_.resize(signal::kTableCapacity);
    std::vector<double> scratch(signal::scratch_size(loaded_->recipe));
    const engine::Status s = engine::make_table(*loaded_, storage_, scratch, table_);
    ASSERT_TRUE(s) << s.message();

    hal::simlink::SimLinkConfig sc;
    sc.input_baseline.assign(kU0, kU0 + kInputs);
    sc.output_baseline.assign(kY0, kY0 + kOutputs);
    sc.command_register = true;
    sc.exchange_time = std::chrono::milliseconds(2);
    bus_ = std::make_unique<hal::simlink::SimLinkFieldBus>(sim::library_plant("alatiqi4x4"), 1.0,
                                                           sc, &clock_);
    config_ = engine_config();
    log_path_ = (std::filesystem::temp_directory_path() /
                 ("excite_engine_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".csv"))
                    .string();
    script_.states.reserve(20000);
  }

  void TearDown() override { std::filesystem::remove(log_path_); }

  engine::EngineConfig engine_config() const {
    engine::EngineConfig c;
    c.inputs = kInputs;
    c.values = static_cast<std::uint32_t>(bus_->value_count());
    for (std::uint32_t i = 0; i < kInputs; ++i) {
      c.input[i] = {kU0[i] - 20.0, kU0[i] + 20.0, 5.0, bus_->readback_index(i)};
    }
    for (std::uint32_t j = 0; j < kOutputs; ++j) {
      c.test[j] = {true, kY0[j] - kTestBand, kY0[j] + kTestBand, 10.0};
    }
    c.ramp_ticks = 5;
    c.resume_dwell_ticks = 10;
    c.suspend_timeout_ticks = 200;
    c.comm_fail_limit = 3;
    c.heartbeat_echo = bus_->heartbeat_echo_index();
    c.heartbeat_max_lag = 3;
    c.command_value = bus_->command_index();
    return c;
  }

  // Configures, arms (reading the live plant), runs until safe with the log thread.
  app::RunStats run(engine::Command first = engine::Command::start) {
    EXPECT_TRUE(engine_.configure(config_, table_));
    ring_storage_.assign(ring_records_, engine::TickRecord{});
    ring_ = std::make_unique<engine::SpanLogRing>(ring_storage_);
    app::Runner runner(engine_, *bus_, clock_, *ring_, std::chrono::seconds(60));
    runner.set_observer(&script_);
    const engine::Status armed = runner.arm();
    EXPECT_TRUE(armed) << armed.message();
    std::FILE* file = std::fopen(log_path_.c_str(), "w");
    EXPECT_NE(file, nullptr);
    app::LogLayout layout;
    layout.header.plant = "alatiqi4x4 (simlink)";
    layout.header.plan = "example plan";
    layout.sample_time_min = 1.0;
    layout.header.sample_time_min = 1.0;
    layout.header.inputs = inputs_;
    layout.header.outputs = outputs_;
    layout.output_values = {0, 1, 2, 3};
    app::LogDrain drain(*ring_, file, layout);
    drain.set_row_delay(row_delay_);
    EXPECT_TRUE(drain.write_header());
    drain.start();
    if (first != engine::Command::none) commands_.post(first);
    const app::RunStats stats = runner.run(commands_, nullptr, max_ticks_);
    drain.stop();
    rows_written_ = drain.rows_written();
    std::fclose(file);
    return stats;
  }

  runlog::RunLog read_log() {
    runlog::ReadResult r = runlog::read_run_log(log_path_);
    EXPECT_TRUE(r.ok()) << (r.error ? r.error->to_string() : "");
    return r.log;
  }

  static constexpr std::size_t kRing = 8192;
  std::unique_ptr<plan::Plan> plan_;
  std::unique_ptr<plan::Plan> loaded_;
  std::vector<double> storage_;
  signal::TableView table_;
  hal::VirtualClock clock_;
  std::unique_ptr<hal::simlink::SimLinkFieldBus> bus_;
  engine::EngineConfig config_;
  engine::Engine engine_;
  std::size_t ring_records_ = kRing;
  std::vector<engine::TickRecord> ring_storage_;
  std::unique_ptr<engine::SpanLogRing> ring_;
  app::CommandMailbox commands_;
  Script script_;
  std::string log_path_;
  std::chrono::microseconds row_delay_{0};
  std::uint64_t max_ticks_ = 0;
  std::uint64_t rows_written_ = 0;
  double held_[kInputs] = {};
  const runlog::Channel inputs_[kInputs] = {
      {"L", "kmol/min"}, {"V", "kmol/min"}, {"S", "kmol/min"}, {"F", "kmol/min"}};
  const runlog::Channel outputs_[kOutputs] = {{"xD", "-"}, {"xS", "-"}, {"xB", "-"}, {"T", "K"}};
};

}  // namespace excite::testing
