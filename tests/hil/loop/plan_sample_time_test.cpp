// SPDX-License-Identifier: MIT
// Issue 24 §4, with the real processes: in the loop the plant server's sample time comes
// from the plan being streamed (its header), not from the plant's case study looked up by
// name, and excite-plant refuses a plan at another sample time (--plan) before serving.
#include <gmock/gmock.h>

#include <csignal>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

#include "firmware/plan/codec.hpp"
#include "host/loop/stream.hpp"
#include "loop_facts.hpp"
#include "loop_fixture.hpp"

namespace excite::test {
namespace {

using ::testing::HasSubstr;
using ::testing::Not;

class PlanSampleTime : public LoopTest {
 protected:
  // The plan from `excite design`, with its sample time set to `minutes` (the rows, their
  // count and the recipe unchanged): a plan the case study's T does not describe.
  fs::path plan_at(double minutes) {
    const fs::path designed = design(kPlant, "prbsUnc");
    std::ifstream in(designed, std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
    auto p = std::make_unique<plan::Plan>();
    EXPECT_TRUE(plan::decode(bytes, *p).is_ok());
    p->meta.sample_time_min = minutes;
    std::vector<std::uint8_t> out(plan::max_encoded_size());
    const plan::EncodeResult r = plan::encode(*p, out);
    EXPECT_TRUE(r.status.is_ok()) << r.status.message();
    const fs::path file = path("at-" + std::to_string(minutes) + ".plan");
    std::ofstream(file, std::ios::binary)
        .write(reinterpret_cast<const char*>(out.data()), static_cast<std::streamsize>(r.size));
    return file;
  }
};

TEST_F(PlanSampleTime, PlantServerRefusesAPlanAtAnotherSampleTime) {
  // GIVEN plant.toml at the case study's T = 1 min and a plan at 0.5 min
  loop_config(kPlant, 1502, "");
  const fs::path half = plan_at(0.5);
  // WHEN excite-plant is told the plan it will be streamed
  PlantRunner plant({"--config", path("plant.toml").string(), "--plan", half.string(),
                     "--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep"},
                    path("plant.stderr"));
  // THEN it serves nothing and says which plan, its T and the plant's
  EXPECT_FALSE(plant.wait_listening().has_value());
  EXPECT_EQ(plant.wait_exit().value_or(-1), 2);
  EXPECT_THAT(plant.stderr_text(),
              HasSubstr(half.string() +
                        ": sample_time_min = 0.5, expected the plant's sample time, 1 min (" +
                        path("plant.toml").string() + ": plant.sample_time_min)"));
  EXPECT_THAT(plant.first_line(), Not(HasSubstr("listening")));
}

TEST_F(PlanSampleTime, PlantServerServesAPlanAtItsSampleTime) {
  loop_config(kPlant, 1502, "");
  const fs::path same = plan_at(1.0);
  PlantRunner plant({"--config", path("plant.toml").string(), "--plan", same.string(),
                     "--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep"},
                    path("plant.stderr"));
  EXPECT_TRUE(plant.wait_listening().has_value()) << plant.stderr_text();
  EXPECT_EQ(plant.stop(SIGTERM).value_or(-1), 0) << plant.stderr_text();
}

TEST_F(PlanSampleTime, LoopConfigTakesThePlansSampleTimeAndThePlantServesIt) {
  const fs::path half = plan_at(0.5);
  loop_config(kPlant, 1502, "--plan " + half.string());
  std::ifstream toml(path("plant.toml"));
  const std::string text((std::istreambuf_iterator<char>(toml)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("\nsample_time_min = 0.5\n"));
  PlantRunner plant({"--config", path("plant.toml").string(), "--plan", half.string(),
                     "--modbus-tcp", "127.0.0.1:0", "--clock", "lockstep"},
                    path("plant.stderr"));
  EXPECT_TRUE(plant.wait_listening().has_value()) << plant.stderr_text();
  EXPECT_EQ(plant.stop(SIGTERM).value_or(-1), 0) << plant.stderr_text();
  EXPECT_THAT(plant.stderr_text(), HasSubstr("T = 0.5 min"));
}

TEST_F(PlanSampleTime, TheLoopStreamsAtThePlansSampleTime) {
  // GIVEN a plan at 0.5 min for a plant whose case study says 1 min
  const fs::path half = plan_at(0.5);
  host::LoopRun run;
  run.plan = half;
  run.work_dir = path("loop");
  run.config.plant = kPlant;
  run.programs = {EXCITE_PLANT, EXCITE_GATEWAY};
  // WHEN it is streamed through the real gateway to the real plant server
  const host::LoopResult result = host::stream_in_the_loop(run);
  // THEN both logs, and the plant's configuration, carry the plan's T
  EXPECT_DOUBLE_EQ(result.log.sample_time_min, 0.5);
  const runlog::RunLog plant = read_log_or_fail(result.plant_log);
  EXPECT_DOUBLE_EQ(plant.sample_time_min, 0.5);
  std::ifstream toml(run.work_dir / "plant.toml");
  const std::string text((std::istreambuf_iterator<char>(toml)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("\nsample_time_min = 0.5\n"));
}

}  // namespace
}  // namespace excite::test
