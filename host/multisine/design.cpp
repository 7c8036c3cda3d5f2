// SPDX-License-Identifier: MIT
#include "host/multisine/design.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>

namespace excite::host::multisine {
namespace {

constexpr double kPi = std::numbers::pi;

std::string number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

// Smallest integer ≥ x, tolerant of rounding just above an integer.
std::uint32_t ceil_integer(double x, const std::string& what) {
  const double c = std::ceil(x - 1e-9 * std::max(1.0, std::abs(x)));
  if (!(c >= 0.0) || c > 4.0e9) {
    throw std::invalid_argument("multisine design: " + what + " = " + number(x) +
                                " is out of range for a sample count");
  }
  return static_cast<std::uint32_t>(c);
}

class Explanation {
 public:
  explicit Explanation(std::string procedure) : procedure_(std::move(procedure)) {}
  void note(std::string line) { lines_.push_back(std::move(line)); }
  // Records "equation: lhs relation rhs" and throws when it does not hold.
  void require(const std::string& equation, const std::string& text, double lhs,
               const std::string& relation, double rhs) {
    const bool holds = relation == "<"    ? lhs < rhs
                       : relation == "<=" ? lhs <= rhs * (1.0 + 1e-12)
                                          : false;
    const std::string line = equation + ": " + text + ": " + number(lhs) + " " + relation + " " +
                             number(rhs) + (holds ? "  holds" : "  FAILS");
    lines_.push_back(line);
    if (!holds) {
      throw std::invalid_argument(procedure_ + ": inequality " + equation + " fails (" + text +
                                  "): " + number(lhs) + " is not " + relation + " " + number(rhs) +
                                  ", off by " + number(lhs - rhs));
    }
  }
  std::vector<std::string> take() { return std::move(lines_); }

 private:
  std::string procedure_;
  std::vector<std::string> lines_;
};

void check_request(const DesignRequest& r, const char* procedure) {
  const std::string where(procedure);
  auto positive = [&](double value, const char* field) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(where + ": " + field + " = " + number(value) +
                                  ", expected a finite value > 0");
    }
  };
  positive(r.tau_low, "tau_low");
  positive(r.tau_high, "tau_high");
  positive(r.alpha, "alpha");
  positive(r.beta, "beta");
  if (r.sample_time != 0.0) positive(r.sample_time, "sample_time");
  if (r.channels == 0) throw std::invalid_argument(where + ": channels = 0, expected >= 1");
}

// ω_L, ω_H (4.4.10) and T, with their explanation lines.
void band_and_sample_time(const DesignRequest& r, Explanation& why, MultisineDesign& d,
                          const char* nyquist_equation) {
  d.omega_low = 1.0 / (r.beta * r.tau_high);
  d.omega_high = r.alpha / r.tau_low;
  why.note("4.4.10: ω_L = 1/(β τ_H) = 1/(" + number(r.beta) + "·" + number(r.tau_high) +
           ") = " + number(d.omega_low) + " rad/time unit; ω_H = α/τ_L = " + number(r.alpha) + "/" +
           number(r.tau_low) + " = " + number(d.omega_high) + " rad/time unit");
  why.require("4.4.10", "band not empty, ω_L < ω_H", d.omega_low, "<", d.omega_high);
  if (r.sample_time > 0.0) {
    d.sample_time = r.sample_time;
    why.note("T = " + number(d.sample_time) + " (given)");
  } else {
    d.sample_time = 0.6 / d.omega_high;
    why.note("T = 0.6/ω_H = " + number(d.sample_time) + " (chosen; thesis remark after Table 4.6)");
  }
  why.require(nyquist_equation, "band below Nyquist, T < π/ω_H", d.sample_time, "<",
              kPi / d.omega_high);
}

void check_capacity(const DesignRequest& r, Explanation& why, const MultisineDesign& d) {
  if (r.max_period == 0) return;
  why.require("capacity", "period N_s ≤ max_period (samples)", d.period, "<=", r.max_period);
}

}  // namespace

MultisineDesign design_standard(const DesignRequest& r) {
  check_request(r, "multisine design A2");
  Explanation why("multisine design A2");
  MultisineDesign d;
  band_and_sample_time(r, why, d, "4.4.26");
  const double T = d.sample_time;
  const double n_min = 2.0 * kPi / (T * d.omega_low);
  d.period = ceil_integer(n_min, "N_s");
  why.note("4.4.27: N_s = " + std::to_string(d.period) +
           ", the smallest integer ≥ 2π/(T ω_L) = " + number(n_min));
  const double lines_min = d.period * T * d.omega_high / (2.0 * kPi);
  d.lines = ceil_integer(lines_min, "n_s");
  why.note("4.4.28: n_s = " + std::to_string(d.lines) +
           ", the smallest integer ≥ N_s T ω_H/(2π) = " + number(lines_min));
  why.require("4.4.28", "too few lines, n_s ≥ 2", 2.0, "<=", d.lines);
  why.require("4.4.26", "top line below Nyquist, 2 n_s < N_s", 2.0 * d.lines, "<", d.period);
  why.require("4.4.25", "ω_H − ω_L ≤ 2π(n_s − 1)/(N_s T)", d.omega_high - d.omega_low,
              "<=", 2.0 * kPi * (d.lines - 1.0) / (d.period * T));
  check_capacity(r, why, d);
  d.delta = 0;
  d.slots = 1;
  why.note("lines 1 … " + std::to_string(d.lines) + " of a " + std::to_string(d.period) +
           "-sample period, ω from " + number(2.0 * kPi / (d.period * T)) + " to " +
           number(2.0 * kPi * d.lines / (d.period * T)));
  d.explanation = why.take();
  return d;
}

MultisineDesign design_zippered(const DesignRequest& r) {
  check_request(r, "multisine design A3");
  Explanation why("multisine design A3");
  MultisineDesign d;
  band_and_sample_time(r, why, d, "4.4.29");
  const double T = d.sample_time;
  const double n = static_cast<double>(r.channels) + r.shared_slots;  // interleaved slots
  const double delta = r.delta;
  d.delta = r.delta;
  d.slots = r.channels + r.shared_slots;
  why.note("n = " + number(n) + " interleaved slots (" + std::to_string(r.channels) +
           " channels + " + std::to_string(r.shared_slots) +
           " shared), δ = " + std::to_string(r.delta));
  const double period_min = 2.0 * kPi * n * (1.0 + delta) / (T * d.omega_low);
  d.period = ceil_integer(period_min, "N_s");
  why.note("4.4.30: N_s = " + std::to_string(d.period) +
           ", the smallest integer ≥ 2π n(1+δ)/(T ω_L) = " + number(period_min));
  const double N = d.period;
  const double lines_min = N * T * d.omega_high / (2.0 * kPi * n) - delta;
  d.lines = ceil_integer(std::max(lines_min, 0.0), "n_s");
  why.note("4.4.31: n_s = " + std::to_string(d.lines) +
           ", the smallest integer ≥ N_s T ω_H/(2π n) − δ = " + number(lines_min));
  const double ns = d.lines;
  why.require("4.4.15", "too few lines: n_s ≥ 2 (n_s − 1 > 0)", 2.0, "<=", ns);
  why.require("4.4.14 (lower)", "(1+δ) ω_H/ω_L ≤ n_s + δ",
              (1.0 + delta) * d.omega_high / d.omega_low, "<=", ns + delta);
  why.require("4.4.14 (upper)", "n_s + δ ≤ N_s/(2n)", ns + delta, "<=", N / (2.0 * n));
  why.require("4.4.13", "top line below Nyquist, 2 n(n_s + δ) < N_s", 2.0 * n * (ns + delta), "<",
              N);
  why.require(
      "4.4.15", "T ≤ min(π/ω_H, π/(ω_H − ω_L) · (n_s − 1)/(n_s + δ))", T, "<=",
      std::min(kPi / d.omega_high, kPi / (d.omega_high - d.omega_low) * (ns - 1.0) / (ns + delta)));
  why.require("4.4.16 (lower)", "max(2n(n_s+δ), 2π n(1+δ)/(ω_L T)) ≤ N_s",
              std::max(2.0 * n * (ns + delta), period_min), "<=", N);
  why.require("4.4.16 (upper)", "N_s ≤ 2π n(n_s+δ)/(ω_H T)", N,
              "<=", 2.0 * kPi * n * (ns + delta) / (d.omega_high * T));
  why.require("4.4.17 (lower)", "(ω_H − ω_L) N_s T/(2π n) + 1 + δ ≤ n_s + δ",
              (d.omega_high - d.omega_low) * N * T / (2.0 * kPi * n) + 1.0 + delta,
              "<=", ns + delta);
  why.require("4.4.17 (upper)", "n_s + δ ≤ N_s/(2n)", ns + delta, "<=", N / (2.0 * n));
  why.require("4.4.25", "ω_H − ω_L ≤ n 2π/(N_s T) (n_s − 1)", d.omega_high - d.omega_low,
              "<=", n * 2.0 * kPi / (N * T) * (ns - 1.0));
  check_capacity(r, why, d);
  why.note("band lines of slot j: n(δ+k) + j, k = 0 … " + std::to_string(d.lines - 1) +
           " (4.4.18/4.4.21), lowest ω = " + number(2.0 * kPi * (n * delta + 1.0) / (N * T)) +
           ", highest ω = " + number(2.0 * kPi * n * (delta + ns) / (N * T)));
  d.explanation = why.take();
  return d;
}

}  // namespace excite::host::multisine
