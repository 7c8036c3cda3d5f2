// SPDX-License-Identifier: MIT
// JᵀJ of one Levenberg–Marquardt iteration (issue 44): host::normal_matrix, a column at a time
// by matrix–vector products, against Eigen's symmetric rank update (what bounded_lm used
// before), in the same process, for the row fits' shapes: N = 4 082 rows (the case study's
// gateway log), P = 3–6 (an element fitted alone in the structure search) and 12–23 (a 4-input
// row). After the benchmarks it prints, per P, the time of each and their ratio, and the
// largest difference of the two relative to the largest entry (the sums are ordered otherwise).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>

#include "host/identify/bounded_lm.hpp"

namespace {

constexpr Eigen::Index kRows = 4082;
constexpr int kShapes[] = {3, 4, 6, 12, 16, 23};

Eigen::MatrixXd jacobian(Eigen::Index parameters) {
  std::srand(2026);
  return Eigen::MatrixXd::Random(kRows, parameters);
}

void rank_update(const Eigen::MatrixXd& J, Eigen::MatrixXd& H) {
  H = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  H.selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
  H.triangularView<Eigen::StrictlyUpper>() = H.transpose();
}

void BM_RankUpdate(benchmark::State& state) {
  const Eigen::MatrixXd J = jacobian(state.range(0));
  Eigen::MatrixXd H;
  for (auto _ : state) {
    rank_update(J, H);
    benchmark::DoNotOptimize(H.data());
  }
}

void BM_NormalMatrix(benchmark::State& state) {
  const Eigen::MatrixXd J = jacobian(state.range(0));
  Eigen::MatrixXd H;
  for (auto _ : state) {
    excite::host::normal_matrix(J, H);
    benchmark::DoNotOptimize(H.data());
  }
}

void shapes(benchmark::internal::Benchmark* b) {
  for (const int p : kShapes) b->Arg(p);
}
BENCHMARK(BM_RankUpdate)->Apply(shapes);
BENCHMARK(BM_NormalMatrix)->Apply(shapes);

// Microseconds per call, the least of five batches of 200.
template <class F>
double microseconds(F f) {
  double best = 1e300;
  for (int batch = 0; batch < 5; ++batch) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < 200; ++i) f();
    const std::chrono::duration<double, std::micro> d = std::chrono::steady_clock::now() - start;
    best = std::min(best, d.count() / 200.0);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  std::printf("\nJᵀJ, N = %ld rows: microseconds per call (least of 5 × 200)\n",
              static_cast<long>(kRows));
  std::printf(" P  rank update  normal_matrix  ratio  largest difference\n");
  for (const int p : kShapes) {
    const Eigen::MatrixXd J = jacobian(p);
    Eigen::MatrixXd a;
    Eigen::MatrixXd b;
    const double t_rank = microseconds([&] { rank_update(J, a); });
    const double t_columns = microseconds([&] { excite::host::normal_matrix(J, b); });
    const double difference = (a - b).cwiseAbs().maxCoeff() / a.cwiseAbs().maxCoeff();
    std::printf("%2d  %11.1f  %13.1f  %5.2f  %.1e\n", p, t_rank, t_columns, t_rank / t_columns,
                difference);
  }
  return 0;
}
