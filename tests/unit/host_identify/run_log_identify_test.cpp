// SPDX-License-Identifier: MIT
// The whole downstream hop: a run written through the run-log writer into a real file, read
// back by the reader, identified. The log is the only thing the two sides share.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "firmware/runlog/writer.hpp"
#include "host/identify/identify.hpp"
#include "host/identify/run_data.hpp"
#include "test_data.hpp"

namespace excite::host {
namespace {

TEST(RunLogToIdentify, ALoggedNoiseFreeRunGivesBackThePlant) {
  const std::vector<ElementModel> truth = {
      {2.0, 1.3, 20.0, 5.0}, {-1.5, 4.7, 12.0, 3.0}, {0.8, 7.25, 30.0, 2.0}, {1.2, 0.4, 8.0, 6.0}};
  const double T = 0.5;
  const Eigen::MatrixXd U = testing::prbs_inputs(2, 6, 16, 31, 2016, 1.0);
  const Eigen::MatrixXd Y = testing::plant_outputs(truth, 2, 2, T, U);

  char path[] = "/tmp/excite_identify_log_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  std::FILE* f = fdopen(fd, "wb");
  const std::array<runlog::Channel, 2> inputs = {{{"L", "kmol/min"}, {"V", "kmol/min"}}};
  const std::array<runlog::Channel, 2> outputs = {{{"xD", "mol/mol"}, {"xB", "mol/mol"}}};
  const runlog::Header header{"2x2 test plant", "prbs", T, inputs, outputs};
  std::array<char, runlog::max_row_chars(2, 2)> row_buffer{};
  std::array<char, 1024> header_buffer{};
  ASSERT_EQ(runlog::FileWriter(f, header, header_buffer).write_header(), runlog::WriteStatus::ok);
  runlog::FileWriter writer(f, header, row_buffer);
  const std::array<double, 2> baseline = {2.706, 3.206};
  for (Eigen::Index k = 0; k < U.rows(); ++k) {
    const std::array<double, 2> du = {U(k, 0), U(k, 1)};
    const std::array<double, 2> u = {baseline[0] + du[0], baseline[1] + du[1]};
    const std::array<double, 2> dy = {Y(k, 0), Y(k, 1)};
    ASSERT_EQ(
        writer.write_row({static_cast<double>(k) * T, static_cast<std::uint64_t>(k), du, u, dy, 0}),
        runlog::WriteStatus::ok);
  }
  std::fclose(f);

  const runlog::ReadResult read = runlog::read_run_log(path);
  std::remove(path);
  ASSERT_TRUE(read.ok()) << read.error->to_string();
  const RunData data = run_data(read.log);
  EXPECT_EQ(data.U, U);  // bit-exact through the text file
  EXPECT_EQ(data.Y, Y);
  const IdentificationResult r = identify(data.U, data.Y, data.sample_time_min);
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 2; ++i) {
      const ElementModel t = truth[static_cast<std::size_t>(2 * j + i)];
      const ElementModel e = r.model.element(j, i).value;
      EXPECT_NEAR(e.gain, t.gain, 1e-3 * std::abs(t.gain));
      EXPECT_NEAR(e.delay_min, t.delay_min, 1e-3 * t.delay_min);
      EXPECT_NEAR(e.tau1_min, t.tau1_min, 1e-3 * t.tau1_min);
      EXPECT_NEAR(e.tau2_min, t.tau2_min, 1e-3 * t.tau2_min);
    }
  }
}

// Format v2: rows after skipped ticks or a plant restart are not one equally spaced run;
// run_data() names the row instead of fitting the gap as dynamics.
TEST(RunLogToIdentify, SkippedOrDiscontinuousRowsAreRefusedByName) {
  const std::string head =
      "# excite run log v2\n# plant: p\n# plan: q\n# sample_time_min: 1\n# inputs: u\n"
      "# outputs: y\n# units: u=- y=-\nt_min,k,du_u,u_u,dy_y,flags,state\n"
      "0,0,0,0,0,0,running\n1,1,0,0,0,0,running\n";
  const runlog::ReadResult skipped =
      runlog::parse_run_log(head + "4,4,0,0,0,32,running\n", "skipped.csv");
  ASSERT_TRUE(skipped.ok()) << skipped.error->to_string();
  try {
    (void)run_data(skipped.log);
    FAIL() << "a skipped row was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("row 3 (k = 4) is flagged skipped"), std::string::npos)
        << e.what();
  }
  const runlog::ReadResult restarted =
      runlog::parse_run_log(head + "2,2,0,0,0,64,running\n", "restart.csv");
  ASSERT_TRUE(restarted.ok()) << restarted.error->to_string();
  EXPECT_THROW((void)run_data(restarted.log), std::invalid_argument);
  const runlog::ReadResult clean =
      runlog::parse_run_log(head + "2,2,0,0,0,0,running\n", "clean.csv");
  ASSERT_TRUE(clean.ok());
  EXPECT_EQ(run_data(clean.log).U.rows(), 3);
}

}  // namespace
}  // namespace excite::host
