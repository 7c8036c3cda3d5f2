// SPDX-License-Identifier: MIT
// The row fit's kernels that run several recursions side by side (issue 44) give the numbers of
// the one-at-a-time code they replaced, bit for bit: the structure search's path, hence every
// model, depends on the last bit of a residual. normal_matrix sums in another order: to
// rounding.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "host/identify/bounded_lm.hpp"
#include "host/identify/segments.hpp"
#include "test_data.hpp"

namespace excite::host::side_by_side_test {
namespace {

constexpr double kT = 1.0;
constexpr Eigen::Index kRows = 300;

// Three segments, the last shorter than a row fit's block of eight and than most delays.
std::vector<Segment> three_segments() {
  return {{0, 170}, {170, 295}, {295, kRows}};
}

bool same_bits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), static_cast<std::size_t>(a.size()) * sizeof(double)) == 0;
}

std::span<double> span_of(Eigen::VectorXd& v) {
  return {v.data(), static_cast<std::size_t>(v.size())};
}

// Six elements (two groups: four side by side, then two) of different orders and delays, one
// delay longer than the last segment.
std::vector<ElementModel> six_elements() {
  ElementModel first = with_structure(ElementModel{}, Structure::first_order);
  first.gain = 1.0;
  first.delay_min = 0.0;
  first.tau1_min = 12.0;
  ElementModel lead = with_structure(ElementModel{}, Structure::two_poles_zero);
  lead.gain = 1.0;
  lead.delay_min = 2.4;
  lead.tau1_min = 30.0;
  lead.tau2_min = 6.0;
  lead.zero_min = -4.0;
  ElementModel ringing = with_structure(ElementModel{}, Structure::underdamped_lag_zero);
  ringing.gain = 1.0;
  ringing.delay_min = 7.3;
  ringing.tau1_min = 9.0;
  ringing.zero_min = 3.0;
  ringing.natural_min = 5.0;
  ringing.damping = 0.3;
  return {first,   ElementModel{1.0, 1.5, 25.0, 7.0}, lead,
          ringing, ElementModel{1.0, 9.6, 4.0, 1.0},  first};
}

TEST(SideBySide, TheRowsSimulationIsTheElementsSummedOneAtATime) {
  const std::vector<ElementModel> elements = six_elements();
  const std::vector<double> gains{1.3, -0.7, 2.1, 0.05, -4.0, 0.6};
  const Eigen::MatrixXd U = [] {
    Eigen::MatrixXd u(kRows, 6);
    for (Eigen::Index j = 0; j < 6; ++j)
      u.col(j) = testing::random_levels(kRows, static_cast<unsigned>(j + 1));
    return u;
  }();
  std::vector<sim::DiscreteTerm> discrete;
  for (const ElementModel& g : elements) discrete.push_back(discretise(g, kT));
  const std::vector<Segment> segments = three_segments();

  Eigen::VectorXd one_at_a_time = Eigen::VectorXd::Zero(kRows);
  Eigen::VectorXd z(kRows);
  std::vector<const sim::DiscreteTerm*> terms;
  std::vector<std::span<const double>> inputs;
  for (std::size_t e = 0; e < elements.size(); ++e) {
    const auto u = U.col(static_cast<Eigen::Index>(e));
    inputs.emplace_back(u.data(), static_cast<std::size_t>(kRows));
    terms.push_back(&discrete[e]);
    simulate_segments(discrete[e], inputs.back(), span_of(z), segments);
    one_at_a_time += gains[e] * z;
  }
  Eigen::VectorXd side_by_side(kRows);
  std::vector<double> scratch;
  simulate_sum_segments(terms, gains, inputs, span_of(side_by_side), segments, scratch);
  EXPECT_TRUE(same_bits(side_by_side, one_at_a_time));
  EXPECT_GT(one_at_a_time.norm(), 1.0);  // the elements moved the output

  // A group of one, two or three alone (the remainder of the group of four) too.
  for (std::size_t n = 1; n <= 3; ++n) {
    Eigen::VectorXd alone = Eigen::VectorXd::Zero(kRows);
    for (std::size_t e = 0; e < n; ++e) {
      simulate_segments(discrete[e], inputs[e], span_of(z), segments);
      alone += gains[e] * z;
    }
    simulate_sum_segments(std::span(terms).first(n), std::span(gains).first(n),
                          std::span(inputs).first(n), span_of(side_by_side), segments, scratch);
    EXPECT_TRUE(same_bits(side_by_side, alone)) << n << " elements";
  }
}

TEST(SideBySide, EachColumnIsAllPoleFilteredAsAlone) {
  const std::vector<std::array<double, kMaxPoles>> poles{{-0.9, 0.0, 0.0},
                                                         {-1.6, 0.64, 0.0},
                                                         {-2.2, 1.6, -0.38},
                                                         {-1.2, 0.5, -0.06},
                                                         {-0.5, 0.0, 0.0}};
  Eigen::MatrixXd X(kRows, 5);
  for (Eigen::Index j = 0; j < 5; ++j)
    X.col(j) = testing::random_levels(kRows, static_cast<unsigned>(10 + j));
  Eigen::MatrixXd alone = X;
  const std::vector<Segment> segments = three_segments();
  for (Eigen::Index j = 0; j < 5; ++j) {
    Eigen::VectorXd c = alone.col(j);
    for (const Segment& s : segments) {
      all_pole_filter(poles[static_cast<std::size_t>(j)],
                      span_of(c).subspan(static_cast<std::size_t>(s.begin),
                                         static_cast<std::size_t>(s.end - s.begin)));
    }
    alone.col(j) = c;
  }
  all_pole_filter_columns(poles, X, segments);
  for (Eigen::Index j = 0; j < 5; ++j) {
    EXPECT_TRUE(same_bits(X.col(j), alone.col(j))) << "column " << j;
    EXPECT_NE(X(kRows - 1, j),
              testing::random_levels(kRows, static_cast<unsigned>(10 + j))(kRows - 1));
  }
}

TEST(SideBySide, TheLaggedSumIsTheLaggedTermsAddedInTurn) {
  const Eigen::VectorXd w = testing::random_levels(kRows, 21);
  const Eigen::VectorXd v = testing::random_levels(kRows, 22);
  // Lags from 0 to past the last segment's length (6 rows), both sources, the terms' order
  // not sorted by lag.
  const std::vector<LaggedTerm> terms{{0.31, w.data(), 3},  {-1.7, w.data(), 0},
                                      {2.2, w.data(), 9},   {0.004, v.data(), 1},
                                      {-0.52, v.data(), 2}, {1.1, w.data(), 4}};
  const std::vector<Segment> segments = three_segments();
  Eigen::VectorXd in_turn = Eigen::VectorXd::Zero(kRows);
  for (const LaggedTerm& t : terms)
    add_lagged(in_turn, t.src == w.data() ? w : v, t.lag, t.c, segments);
  Eigen::VectorXd one_pass = Eigen::VectorXd::Constant(kRows, 99.0);  // every row written
  lagged_sum(one_pass, terms, segments);
  EXPECT_TRUE(same_bits(one_pass, in_turn));
  EXPECT_EQ(one_pass(295), -1.7 * w(295));  // a segment's first row: the lag-0 term only
}

TEST(SideBySide, TheNormalMatrixIsJTransposedJ) {
  for (const Eigen::Index columns : {1, 3, 16, 23}) {
    const Eigen::MatrixXd J = Eigen::MatrixXd::Random(kRows, columns);
    Eigen::MatrixXd H;
    normal_matrix(J, H);
    const Eigen::MatrixXd reference = J.transpose() * J;
    EXPECT_LT((H - reference).cwiseAbs().maxCoeff(), 1e-13 * reference.cwiseAbs().maxCoeff())
        << columns << " columns";
    EXPECT_TRUE((H.array() == H.transpose().array()).all())
        << "symmetric, " << columns << " columns";
  }
}

}  // namespace
}  // namespace excite::host::side_by_side_test
