// SPDX-License-Identifier: MIT
#include "sim/library/perturb.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include "sim/library/library.hpp"

namespace excite::sim {
namespace {

// splitmix64 (Steele, Lea & Flood 2014): a fixed, portable stream from one 64-bit seed.
class Draws {
 public:
  explicit Draws(std::uint64_t seed) : state_(seed ^ 0x7065727475726221ULL) {}  // "perturb!"
  // 1 + δ, δ uniform in [−fraction, +fraction).
  double factor(double fraction) {
    state_ += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    const double r = static_cast<double>(z >> 11) * 0x1.0p-53;  // [0, 1)
    return 1.0 + fraction * (2.0 * r - 1.0);
  }

 private:
  std::uint64_t state_;
};

void check(double percent, const std::string& text) {
  if (!std::isfinite(percent) || percent < 0.0 || percent >= kMaxPerturbPercent) {
    throw std::invalid_argument("--perturb = " + text +
                                ", expected a number of percent, 0 <= X < 100 (each gain, time "
                                "constant and delay of the true plant within +-X %)");
  }
}

// p(s) → p(f·s): coefficient k (of s^k) times f^k.
void time_scale(sim::Polynomial& p, double f) {
  double scale = 1.0;
  for (double& c : p) {
    c *= scale;
    scale *= f;
  }
}

}  // namespace

std::string percent_text(double percent) {
  char buffer[32];
  const auto [end, error] = std::to_chars(buffer, buffer + sizeof buffer, percent);
  return error == std::errc() ? std::string(buffer, end) : std::string("?");
}

void check_perturb(double percent) {
  check(percent, percent_text(percent));
}

void check_perturbable(const std::string& plant, double percent) {
  check_perturb(percent);
  if (percent > 0.0) {
    const std::vector<std::string> linear = sim::library_plant_names();
    if (std::find(linear.begin(), linear.end(), plant) == linear.end()) {
      throw std::invalid_argument(
          "--perturb = " + percent_text(percent) + " on plant " + plant +
          ", expected 0 (only a linear library plant has gains, time constants and delays to "
          "perturb)");
    }
  }
}

double parse_perturb(const std::string& text) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size())
    check(std::nan(""), text);
  check(value, text);
  return value;
}

sim::TransferMatrix perturbed_plant(const sim::TransferMatrix& nominal, double percent,
                                    std::uint64_t seed) {
  check_perturb(percent);
  sim::TransferMatrix g = nominal;
  if (percent == 0.0) return g;
  const double fraction = percent / 100.0;
  Draws draw(seed);
  for (int i = 0; i < g.outputs(); ++i) {
    for (int j = 0; j < g.inputs(); ++j) {
      const sim::Element& e = g.element(i, j);
      if (e.is_zero()) continue;
      std::vector<sim::Term> terms = e.terms();
      const double gain = draw.factor(fraction);
      for (sim::Term& t : terms) {
        t.gain *= gain;
        for (sim::Factor& f : t.zeros) time_scale(f.poly, draw.factor(fraction));
        for (sim::Factor& f : t.poles) time_scale(f.poly, draw.factor(fraction));
        t.delay_min *= draw.factor(fraction);
      }
      g.set_element(i, j, sim::Element(std::move(terms), ""));
    }
  }
  return g;
}

}  // namespace excite::sim
