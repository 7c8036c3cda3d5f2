// SPDX-License-Identifier: MIT
// One DMC step for alatiqi4x4 (M = 5, P = 150, T = 1 min) with constraints: MV box and
// move limits on every MV, soft limits on every CV (80 MV rows and about 1200 CV rows in
// the QP). The measured CVs come from a closed loop recorded once, so every pass of the
// benchmark replays the same samples (constraints active at the start, inactive later).
// Against, in the same run: a naive dense step that forms the normal equations
// S_uᵀW_yS_u + W_Δu and factors them afresh (Eigen LLT) every sample — and still only has
// the unconstrained move. Prints µs per step and the ratio (CPU time of this thread).
#include <benchmark/benchmark.h>

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <functional>
#include <vector>

#include "sim/control/dmc.hpp"
#include "sim/control/step_model.hpp"
#include "sim/plants/plant.hpp"

namespace {

using namespace excite::sim;
using namespace excite::sim::control;

constexpr int kSamples = 600;

struct Setup {
  StepModel model;
  DmcSettings settings;
  std::vector<std::vector<double>> y;  // recorded CVs, kSamples × 4
  std::vector<double> setpoint{0.5, 0.0, 0.3, -0.2};
};

const Setup& setup() {
  static const Setup s = [] {
    Setup out;
    auto plant = make_plant("alatiqi4x4");
    out.model = step_model(*plant, 1.0).delayed(1);
    out.settings.prediction_horizon = 150;
    out.settings.control_horizon = 5;
    out.settings.mv.assign(4, MvSettings{-0.6, 0.6, 0.02, 0.1});
    out.settings.cv.assign(4, CvSettings{});
    for (CvSettings& c : out.settings.cv) {
      c.limit_low = -0.55;  // the setpoints lie inside: the limits bind on the way only
      c.limit_high = 0.55;
    }
    DmcController dmc(out.model, out.settings);
    std::vector<double> applied(4, 0.0), y(4), u(4), offsets(4, 0.0);
    plant->reset(1.0);
    for (int k = 0; k < kSamples; ++k) {
      plant->step(applied, y);
      out.y.push_back(y);
      dmc.step(y, out.setpoint, offsets, u);
      applied = u;
    }
    return out;
  }();
  return s;
}

// Without any limit: the DMC prediction and the unconstrained law only.
DmcSettings unconstrained(DmcSettings s) {
  s.mv.assign(4, MvSettings{-kUnlimited, kUnlimited, kUnlimited, 0.1});
  s.cv.assign(4, CvSettings{});
  return s;
}

// The naive step: the free response from an unconstrained DMC (its prediction), then the
// normal equations formed and factored afresh, the first move clipped to the limits.
class NaiveDmc {
 public:
  explicit NaiveDmc(const Setup& s) : s_(s), dmc_(s.model, unconstrained(s.settings)) {}
  void step(const std::vector<double>& y, double* u) {
    double offsets[4] = {0, 0, 0, 0};
    dmc_.step(y, s_.setpoint, offsets, std::span<double>(u, 4));
    const Eigen::MatrixXd& Su = dmc_.dynamic_matrix();
    const Eigen::VectorXd& f = dmc_.free_response();
    Eigen::VectorXd e(f.size());
    for (Eigen::Index i = 0; i < f.size(); ++i)
      e(i) = s_.setpoint[static_cast<std::size_t>(i % 4)] - f(i);
    Eigen::MatrixXd H = Su.transpose() * Su;
    H.diagonal().array() += 0.1;
    const Eigen::VectorXd du = H.llt().solve(Su.transpose() * e);
    for (int j = 0; j < 4; ++j) benchmark::DoNotOptimize(std::clamp(du(j), -0.02, 0.02));
  }
  void reset() { dmc_.reset(); }

 private:
  const Setup& s_;
  DmcController dmc_;
};

void BM_DmcStepConstrained(benchmark::State& state) {
  const Setup& s = setup();
  DmcController dmc(s.model, s.settings);
  std::vector<double> u(4), offsets(4, 0.0);
  int k = 0;
  long iterations = 0;
  for (auto _ : state) {
    if (k == kSamples) {
      k = 0;
      dmc.reset();
    }
    iterations +=
        dmc.step(s.y[static_cast<std::size_t>(k++)], s.setpoint, offsets, u).qp_iterations;
    benchmark::DoNotOptimize(u.data());
  }
  state.counters["qp_rows"] = dmc.constraint_rows();
  state.counters["qp_iter/step"] =
      benchmark::Counter(static_cast<double>(iterations), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_DmcStepConstrained)->Unit(benchmark::kMicrosecond);

void BM_NaiveNormalEquationsStep(benchmark::State& state) {
  const Setup& s = setup();
  NaiveDmc naive(s);
  double u[4];
  int k = 0;
  for (auto _ : state) {
    if (k == kSamples) {
      k = 0;
      naive.reset();
    }
    naive.step(s.y[static_cast<std::size_t>(k++)], u);
  }
}
BENCHMARK(BM_NaiveNormalEquationsStep)->Unit(benchmark::kMicrosecond);

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// Best of five passes over the recorded samples, CPU seconds per step.
double per_step(const std::function<void()>& pass) {
  double best = 1e300;
  for (int r = 0; r < 5; ++r) {
    const double t0 = cpu_seconds();
    pass();
    best = std::min(best, cpu_seconds() - t0);
  }
  return best / kSamples;
}

void compare_with_naive() {
  const Setup& s = setup();
  DmcController dmc(s.model, s.settings);
  NaiveDmc naive(s);
  std::vector<double> u(4), offsets(4, 0.0);
  long qp_iterations = 0;
  int constrained = 0;
  const double ours = per_step([&] {
    dmc.reset();
    qp_iterations = 0;
    constrained = 0;
    for (int k = 0; k < kSamples; ++k) {
      const StepReport r = dmc.step(s.y[static_cast<std::size_t>(k)], s.setpoint, offsets, u);
      qp_iterations += r.qp_iterations;
      constrained += r.active_constraints > 0 ? 1 : 0;
    }
  });
  // The slowest single step (real time is about the worst sample): each step timed alone,
  // the smallest of five passes per sample.
  std::vector<double> single(kSamples, 1e300);
  std::vector<int> single_iterations(kSamples, 0);
  for (int r = 0; r < 5; ++r) {
    dmc.reset();
    for (int k = 0; k < kSamples; ++k) {
      const double t0 = cpu_seconds();
      const StepReport report = dmc.step(s.y[static_cast<std::size_t>(k)], s.setpoint, offsets, u);
      single[static_cast<std::size_t>(k)] =
          std::min(single[static_cast<std::size_t>(k)], cpu_seconds() - t0);
      single_iterations[static_cast<std::size_t>(k)] = report.qp_iterations;
    }
  }
  const auto slowest = std::max_element(single.begin(), single.end()) - single.begin();
  DmcController plain(s.model, unconstrained(s.settings));
  const double prediction_only = per_step([&] {
    plain.reset();
    for (int k = 0; k < kSamples; ++k)
      plain.step(s.y[static_cast<std::size_t>(k)], s.setpoint, offsets, u);
  });
  double v[4];
  const double slow = per_step([&] {
    naive.reset();
    for (int k = 0; k < kSamples; ++k) naive.step(s.y[static_cast<std::size_t>(k)], v);
  });
  std::printf(
      "alatiqi4x4 DMC step, M = 5, P = 150, N = %d, %d QP rows (CPU time, best of 5 passes "
      "over %d samples, %d of them with constraints active, %.2f QP iterations per step):\n"
      "  QDMC step with constraints %.1f us; DMC without limits (prediction + unconstrained "
      "law) %.1f us;\n  naive (that prediction, then the normal equations formed and factored "
      "every step, unconstrained) %.1f us; ratio naive/QDMC %.1fx\n",
      s.model.horizon(), dmc.constraint_rows(), kSamples, constrained,
      static_cast<double>(qp_iterations) / kSamples, ours * 1e6, prediction_only * 1e6, slow * 1e6,
      slow / ours);
  std::printf("  slowest single QDMC step %.1f us (sample %ld, %d QP iterations)\n",
              single[static_cast<std::size_t>(slowest)] * 1e6, static_cast<long>(slowest),
              single_iterations[static_cast<std::size_t>(slowest)]);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  compare_with_naive();
  return 0;
}
