// SPDX-License-Identifier: MIT
#include "host/identify/element.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>

#include "sim/lti/sopdt.hpp"

namespace excite::host {
namespace {

constexpr std::array<int, 3> kFirstOrder{kGain, kDelay, kTp1};
constexpr std::array<int, 4> kTwoPoles{kGain, kDelay, kTp1, kTp2};
constexpr std::array<int, 5> kTwoPolesZero{kGain, kDelay, kTp1, kTp2, kZero};
constexpr std::array<int, 3> kIntegrator{kGain, kDelay, kTp1};
constexpr std::array<int, 4> kUnderdamped{kGain, kDelay, kNatural, kDamping};
constexpr std::array<int, 6> kUnderdampedLagZero{kGain, kDelay, kTp1, kZero, kNatural, kDamping};

}  // namespace

void check_element(const ElementModel& g) {
  const auto fail = [](int p, double v, const char* expected) {
    char value[32];
    std::snprintf(value, sizeof value, "%.6g", v);
    throw std::invalid_argument(std::string(parameter_name(static_cast<Parameter>(p))) + " = " +
                                value + ", expected " + expected);
  };
  for (int p = 0; p < kParameters; ++p) {
    const double v = g[p];
    if (!std::isfinite(v)) fail(p, v, "a finite value");
    if ((p == kDelay || p == kTp1 || p == kTp2 || p == kNatural) && v < 0.0) fail(p, v, "≥ 0");
  }
  if (!(g.damping > 0.0 && g.damping <= 1.0)) fail(kDamping, g.damping, "0 < zeta ≤ 1");
}

namespace {

// The element's continuous parts with vanishing time constants dropped: numerator and
// denominator in ascending powers of s, and the denominator's roots.
struct Parts {
  std::array<double, 2> num{};
  int num_size = 1;
  std::array<double, 4> den{1.0, 0.0, 0.0, 0.0};
  int den_size = 1;
  std::array<std::complex<double>, 3> poles{};
  int pole_count = 0;

  void multiply(std::initializer_list<double> factor) {  // den ← den · factor
    std::array<double, 4> out{};
    int i = 0;
    for (const double f : factor) {
      for (int k = 0; k < den_size; ++k)
        out[static_cast<std::size_t>(k + i)] += f * den[static_cast<std::size_t>(k)];
      ++i;
    }
    den_size += static_cast<int>(factor.size()) - 1;
    den = out;
  }
  void lag(double tau) {  // (1 + s tau), pole −1/tau
    multiply({1.0, tau});
    poles[static_cast<std::size_t>(pole_count++)] = {-1.0 / tau, 0.0};
  }
};

Parts parts(const ElementModel& g, double sample_time_min) {
  check_element(g);
  const double tiny = kVanishingTimeConstant * sample_time_min;
  const Structure s = g.structure;
  Parts p;
  if (is_free(s, kTp1) && g.tau1_min >= tiny) p.lag(g.tau1_min);
  if (is_free(s, kTp2) && g.tau2_min >= tiny) p.lag(g.tau2_min);
  if (is_free(s, kNatural) && g.natural_min >= tiny) {
    const double tn = g.natural_min, z = g.damping;
    p.multiply({1.0, 2.0 * z * tn, tn * tn});
    const double im = std::sqrt(std::max(0.0, 1.0 - z * z)) / tn;
    p.poles[static_cast<std::size_t>(p.pole_count++)] = {-z / tn, im};
    p.poles[static_cast<std::size_t>(p.pole_count++)] = {-z / tn, -im};
  }
  if (s == Structure::integrator) {
    p.multiply({0.0, 1.0});
    p.poles[static_cast<std::size_t>(p.pole_count++)] = {0.0, 0.0};
  }
  p.num[0] = g.gain;
  // A zero needs a pole to be proper; with every time constant vanished it is dropped.
  if (is_free(s, kZero) && std::abs(g.zero_min) >= tiny && p.den_size > 1) {
    p.num[1] = g.gain * g.zero_min;
    p.num_size = 2;
  }
  return p;
}

}  // namespace

const char* to_string(Structure s) {
  switch (s) {
    case Structure::first_order:
      return "first_order";
    case Structure::two_poles:
      return "two_poles";
    case Structure::two_poles_zero:
      return "two_poles_zero";
    case Structure::integrator:
      return "integrator";
    case Structure::underdamped:
      return "underdamped";
    case Structure::underdamped_lag_zero:
      return "underdamped_lag_zero";
  }
  return "?";
}

std::optional<Structure> structure_from_string(std::string_view name) {
  for (int k = 0; k < kStructures; ++k) {
    const auto s = static_cast<Structure>(k);
    if (name == to_string(s)) return s;
  }
  return std::nullopt;
}

const char* parameter_name(Parameter p) {
  switch (p) {
    case kGain:
      return "K";
    case kDelay:
      return "Td";
    case kTp1:
      return "Tp1";
    case kTp2:
      return "Tp2";
    case kZero:
      return "Tz";
    case kNatural:
      return "Tn";
    case kDamping:
      return "zeta";
  }
  return "?";
}

std::span<const int> free_parameters(Structure s) {
  switch (s) {
    case Structure::first_order:
      return kFirstOrder;
    case Structure::two_poles:
      return kTwoPoles;
    case Structure::two_poles_zero:
      return kTwoPolesZero;
    case Structure::integrator:
      return kIntegrator;
    case Structure::underdamped:
      return kUnderdamped;
    case Structure::underdamped_lag_zero:
      return kUnderdampedLagZero;
  }
  return {};
}

bool is_free(Structure s, int parameter) {
  const std::span<const int> f = free_parameters(s);
  return std::find(f.begin(), f.end(), parameter) != f.end();
}

double& ElementModel::operator[](int p) {
  switch (p) {
    case kGain:
      return gain;
    case kDelay:
      return delay_min;
    case kTp1:
      return tau1_min;
    case kTp2:
      return tau2_min;
    case kZero:
      return zero_min;
    case kNatural:
      return natural_min;
    default:
      return damping;
  }
}

double ElementModel::operator[](int p) const {
  return const_cast<ElementModel&>(*this)[p];
}

double ElementModel::static_gain() const {
  if (structure != Structure::integrator || std::isnan(gain) || gain == 0.0) return gain;
  return std::copysign(std::numeric_limits<double>::infinity(), gain);
}

double settling_time_min(const ElementModel& g) {
  const auto part = [&](int p) { return is_free(g.structure, p) ? std::abs(g[p]) : 0.0; };
  const double oscillation = is_free(g.structure, kNatural) ? g.natural_min / g.damping : 0.0;
  return g.delay_min + 7.0 * (part(kTp1) + part(kTp2) + oscillation + part(kZero));
}

ElementModel with_structure(ElementModel g, Structure s) {
  const ElementModel neutral{};
  for (int p = 0; p < kParameters; ++p) {
    if (!is_free(s, p)) g[p] = neutral[p];
  }
  g.structure = s;
  return g;
}

sim::DiscreteTerm discretise(const ElementModel& g, double sample_time_min) {
  if (g.structure == Structure::two_poles) {  // the common case, without building parts
    const double tiny = kVanishingTimeConstant * sample_time_min;
    return sim::discretise_sopdt({g.gain, g.delay_min, g.tau1_min < tiny ? 0.0 : g.tau1_min,
                                  g.tau2_min < tiny ? 0.0 : g.tau2_min},
                                 sample_time_min);
  }
  const Parts p = parts(g, sample_time_min);
  return sim::discretise_zoh(
      std::span<const double>(p.num.data(), static_cast<std::size_t>(p.num_size)),
      std::span<const double>(p.den.data(), static_cast<std::size_t>(p.den_size)),
      std::span<const std::complex<double>>(p.poles.data(), static_cast<std::size_t>(p.pole_count)),
      g.delay_min, sample_time_min);
}

sim::Term to_term(const ElementModel& g, double sample_time_min) {
  const Parts p = parts(g, sample_time_min);
  sim::Term t;
  t.gain = g.gain;
  t.delay_min = g.delay_min;
  if (p.num_size == 2) t.zeros.push_back({{1.0, g.zero_min}, 1});
  if (p.den_size > 1)
    t.poles.push_back({sim::Polynomial(p.den.begin(), p.den.begin() + p.den_size), 1});
  return t;
}

void simulate(const sim::DiscreteTerm& g, std::span<const double> u, std::span<double> y) {
  sim::simulate_term(g, u.data(), y.data(), std::min(u.size(), y.size()));
}

LagTaps lag_taps(const ElementModel& g, double sample_time_min, std::size_t first_lag) {
  return lag_taps(discretise(g, sample_time_min), first_lag);
}

LagTaps lag_taps(const sim::DiscreteTerm& d, std::size_t first_lag) {
  LagTaps t;
  for (std::size_t i = 1; i < static_cast<std::size_t>(d.na) && i <= kMaxPoles; ++i)
    t.a[i - 1] = d.a[i];
  for (int i = 0; i < d.nb; ++i) {
    const auto lag = static_cast<std::size_t>(d.delay_samples + i);
    if (lag >= first_lag && lag < first_lag + kLagWindow)
      t.b[lag - first_lag] = d.b[static_cast<std::size_t>(i)];
  }
  return t;
}

void all_pole_filter(const std::array<double, kMaxPoles>& a, std::span<double> x) {
  double y1 = 0.0;  // y(k−1)
  double y2 = 0.0;  // y(k−2)
  double y3 = 0.0;  // y(k−3)
  for (double& v : x) {
    const double yk = ((v - a[2] * y3) - a[1] * y2) - a[0] * y1;
    y3 = y2;
    y2 = y1;
    y1 = yk;
    v = yk;
  }
}

}  // namespace excite::host
