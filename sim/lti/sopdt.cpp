// SPDX-License-Identifier: MIT
#include "sim/lti/sopdt.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/lti/difference_equation.hpp"

namespace excite::sim {
namespace {

void check(double value, const char* name, bool non_negative) {
  if (!std::isfinite(value) || (non_negative && value < 0.0)) {
    throw std::invalid_argument(
        std::string("SOPDT parameter ") + name + " = " + std::to_string(value) +
        (non_negative ? ", expected a finite value ≥ 0" : ", expected a finite value"));
  }
}

void check(const SopdtParameters& p) {
  check(p.gain, "gain K", false);
  check(p.delay_min, "delay Td (min)", true);
  check(p.tau1_min, "time constant Tp1 (min)", true);
  check(p.tau2_min, "time constant Tp2 (min)", true);
}

}  // namespace

DiscreteTerm discretise_sopdt(const SopdtParameters& p, double sample_time_min) {
  check(p);
  // Denominator (1 + s Tp1)(1 + s Tp2) = 1 + (Tp1 + Tp2) s + Tp1 Tp2 s², poles −1/Tp.
  std::array<double, 3> den{1.0, 0.0, 0.0};
  std::array<std::complex<double>, 2> poles{};
  std::size_t n = 0;
  for (double tau : {p.tau1_min, p.tau2_min}) {
    if (tau == 0.0) continue;
    den[n + 1] = den[n] * tau;  // multiply by (1 + s·tau): shift-add from the top
    for (std::size_t i = n; i >= 1; --i) den[i] += den[i - 1] * tau;
    poles[n] = {-1.0 / tau, 0.0};
    ++n;
  }
  const std::array<double, 1> num{p.gain};
  return discretise_zoh(num, std::span<const double>(den.data(), n + 1),
                        std::span<const std::complex<double>>(poles.data(), n), p.delay_min,
                        sample_time_min);
}

Term sopdt_term(const SopdtParameters& p) {
  check(p);
  Term t;
  t.gain = p.gain;
  t.delay_min = p.delay_min;
  for (double tau : {p.tau1_min, p.tau2_min}) {
    if (tau != 0.0) t.poles.push_back({{1.0, tau}, 1});
  }
  return t;
}

void simulate_term(const DiscreteTerm& d, const double* u, double* y, std::size_t count) {
  std::fill(y, y + count, 0.0);
  const auto delay = static_cast<std::size_t>(d.delay_samples);
  if (delay >= count) return;
  tdf2_accumulate(d, u, y + delay, count - delay);
}

Eigen::VectorXd simulate_sopdt(const SopdtParameters& p, double sample_time_min,
                               const Eigen::VectorXd& u) {
  if (!u.allFinite()) throw std::invalid_argument("input column, expected finite values");
  const DiscreteTerm d = discretise_sopdt(p, sample_time_min);
  Eigen::VectorXd y(u.size());
  simulate_term(d, u.data(), y.data(), static_cast<std::size_t>(u.size()));
  return y;
}

}  // namespace excite::sim
