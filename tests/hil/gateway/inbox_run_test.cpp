// SPDX-License-Identifier: MIT
// Issue 39 §3–§4, `excite test --inbox` as the engineer runs it, against the real gateway and
// the real plant server: the tool reads only the run log of the gateway run it talks to (the
// run named in the inbox's gateway.run), and a test it did not finish leaves nothing a later
// gateway would take.
//  - a whole test through the gateway completes; then the same command again, with that run's
//    log still there and no gateway running, stops with "no gateway run" (before: it completed
//    a whole second test from the stale log, wrote model.json, and left a next.plan behind);
//  - with a gateway.run left by a killed gateway (its pid gone), the tool says the gateway is
//    not running at once instead of waiting out its segment timeout.
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <thread>

#include "../loop/loop_facts.hpp"
#include "../loop/loop_fixture.hpp"

namespace excite::test {
namespace {

using namespace std::chrono_literals;

class ExciteTestInbox : public LoopTest {
 protected:
  std::unique_ptr<GatewayProcess> tool(const std::string& out, const std::string& timeout_min) {
    return std::make_unique<GatewayProcess>(
        EXCITE_TOOL,
        std::vector<std::string>{"test", "--plant", kPlant, "--inbox", path("inbox").string(),
                                 "--run-log", path("gw.csv").string(), "--segment-timeout-min",
                                 timeout_min, "-o", path(out).string()},
        path(out + "-tool").string());
  }
};

TEST_F(ExciteTestInbox, AStaleRunLogWithNoGatewayIsNeverRead) {
  start_loop(kPlant, "--input-range 20 --seed 3");
  std::ofstream(path("gateway.toml"), std::ios::app)
      << "\n[segments]\nawait_s = 60\npreapproved_from = \"excite test segment\"\n";
  fs::create_directories(path("inbox"));
  // A whole test through a gateway: its run log stays behind.
  {
    auto first_tool = tool("out1", "1");
    const fs::path first = path("out1") / "segments" / "segment-0.plan";
    for (int i = 0; i < 3000 && !fs::exists(first); ++i) std::this_thread::sleep_for(10ms);
    ASSERT_TRUE(fs::exists(first)) << first_tool->out() << first_tool->err();
    auto gateway = start_gateway(
        first, {"--clock", "lockstep", "--start", "--segment-inbox", path("inbox").string()});
    const auto rc = first_tool->wait(120s);
    ASSERT_TRUE(rc.has_value()) << first_tool->out() << first_tool->err();
    ASSERT_EQ(*rc, 0) << first_tool->out() << first_tool->err();
    EXPECT_NE(first_tool->out().find("gateway run "), std::string::npos) << first_tool->out();
    gateway->send_line("abort");
    ASSERT_TRUE(gateway->wait(30s).has_value()) << gateway->err();
    EXPECT_FALSE(fs::exists(path("inbox") / "gateway.run")) << "the gateway removes its marker";
  }
  ASSERT_TRUE(fs::exists(path("gw.csv")));

  // The same command again, no gateway running: the stale log is not this test's.
  auto second = tool("out2", "0.05");  // 3 s
  const auto rc2 = second->wait(60s);
  ASSERT_TRUE(rc2.has_value()) << second->out() << second->err();
  EXPECT_NE(*rc2, 0) << second->out() << second->err();
  EXPECT_NE(second->err().find("no gateway run in " + (path("inbox") / "gateway.run").string()),
            std::string::npos)
      << second->err();
  EXPECT_FALSE(fs::exists(path("out2") / "model.json"));
  EXPECT_FALSE(fs::exists(path("inbox") / "next.plan")) << "left for a later gateway";

  // A marker left by a killed gateway: its pid is gone, said at once.
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  waitpid(dead, nullptr, 0);
  std::ofstream(path("inbox") / "gateway.run")
      << "run 0123456789abcdef\npid " << dead << "\nlog " << path("gw.csv").string() << "\n";
  auto third = tool("out3", "10");  // 10 min: the pid, not the timeout, must end it
  const auto rc3 = third->wait(60s);
  ASSERT_TRUE(rc3.has_value()) << third->out() << third->err();
  EXPECT_NE(*rc3, 0) << third->err();
  EXPECT_NE(third->err().find("the gateway of run 0123456789abcdef (pid " + std::to_string(dead) +
                              ") is not running"),
            std::string::npos)
      << third->err();
  EXPECT_FALSE(fs::exists(path("out3") / "model.json"));
  EXPECT_FALSE(fs::exists(path("inbox") / "next.plan"));
  (void)stop_plant_and_read_its_log();
}

}  // namespace
}  // namespace excite::test
