// SPDX-License-Identifier: MIT
#include "host/multisine/guillaume.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unsupported/Eigen/FFT>

#include "host/multisine/lbfgs.hpp"

namespace excite::host::multisine {
namespace {

using Complex = std::complex<double>;

// A line as channel c sees it: amplitude and a fixed phase offset (π for a negative
// direction entry), its phase the variable `var`.
struct Term {
  std::uint32_t index = 0;
  double amplitude = 0.0;
  double offset = 0.0;
  Eigen::Index var = 0;
};

// A snow slot: complex coefficient β_c · (w_re + j w_im) with w at var, var + 1.
struct SnowTerm {
  std::uint32_t index = 0;
  Eigen::Index var = 0;
};

struct Channel {
  std::vector<Term> terms;
  std::vector<SnowTerm> snow;
  double band_power = 0.0;  // Σ A²/2 of its own and shared lines
};

// |z|^(p−1)·sign(z) and |z|^p for the L_p objective; exact integer powers when p is an
// even integer (the usual schedule), std::pow otherwise.
struct PowerKernel {
  double p = 2.0;
  bool even_integer = false;
  unsigned exponent = 1;  // p − 1 when even_integer

  explicit PowerKernel(double p_in) : p(p_in) {
    const double rounded = std::round(p);
    even_integer = rounded == p && static_cast<long>(rounded) % 2 == 0 && p <= 4096.0;
    exponent = even_integer ? static_cast<unsigned>(rounded) - 1U : 1U;
  }
  // Returns h = |z|^(p−1) sign(z); writes |z|^p into `power`.
  double operator()(double z, double& power) const {
    if (even_integer) {
      double result = 1.0;
      double base = z;
      unsigned e = exponent;
      while (e != 0U) {
        if ((e & 1U) != 0U) result *= base;
        base *= base;
        e >>= 1U;
      }
      power = result * z;
      return result;
    }
    const double magnitude = std::abs(z);
    const double h = magnitude > 0.0 ? std::pow(magnitude, p - 1.0) : 0.0;
    power = h * magnitude;
    return z < 0.0 ? -h : h;
  }
};

std::uint32_t next_power_of_two(std::uint64_t wanted) {
  std::uint64_t grid = 4;
  while (grid < wanted) grid *= 2;
  if (grid > (std::uint64_t{1} << 26)) {
    throw std::invalid_argument("guillaume: optimisation grid of " + std::to_string(grid) +
                                " points is too large; lower `oversampling`");
  }
  return static_cast<std::uint32_t>(grid);
}

class CrestObjective {
 public:
  // Variables at or past `held_from` keep their start (their gradient is zero).
  CrestObjective(const MultisineSet& set, const GuillaumeOptions& options,
                 std::uint32_t oversampling, Eigen::Index held_from)
      : set_(set),
        options_(options),
        mean_(options.aggregate == ChannelAggregate::mean),
        held_from_(held_from) {
    const std::size_t n = set.channels.size();
    channels_.resize(n);
    std::uint32_t top = 0;
    Eigen::Index var = 0;
    for (std::size_t c = 0; c < n; ++c) {
      for (const Line& line : set.channels[c]) {
        channels_[c].terms.push_back({line.index, line.amplitude, 0.0, var++});
        start_.push_back(line.phase);
        top = std::max(top, line.index);
      }
    }
    for (const auto& source : set.shared) {
      for (const Line& line : source.lines) {
        for (std::size_t c = 0; c < n; ++c) {
          const double d = source.direction[c];
          if (d == 0.0) continue;
          channels_[c].terms.push_back(
              {line.index, std::abs(d) * line.amplitude, d < 0.0 ? std::numbers::pi : 0.0, var});
        }
        start_.push_back(line.phase);
        ++var;
        top = std::max(top, line.index);
      }
    }
    use_snow_ = options.snow_power_fraction > 0.0 && !set.snow.empty();
    for (std::size_t c = 0; c < n; ++c) {
      for (const Term& term : channels_[c].terms) {
        channels_[c].band_power += term.amplitude * term.amplitude / 2.0;
      }
      if (!use_snow_) continue;
      for (std::uint32_t index : set.snow[c]) {
        channels_[c].snow.push_back({index, var});
        // A small deterministic start off zero, so the first gradient has both parts.
        start_.push_back(1e-3);
        start_.push_back(1e-3 * ((index % 2U) != 0U ? 1.0 : -1.0));
        var += 2;
        top = std::max(top, index);
      }
    }
    for (const auto& channel : channels_) {
      if (channel.band_power <= 0.0) {
        throw std::invalid_argument("guillaume: a channel has no band power (all amplitudes 0)");
      }
    }
    grid_ = next_power_of_two(2ULL * std::max<std::uint32_t>(oversampling, 1) * (top + 1));
    const std::size_t half = grid_ / 2 + 1;
    spectrum_.assign(half, Complex{0.0, 0.0});
    gradient_spectrum_.assign(half, Complex{0.0, 0.0});
    signals_.assign(n, std::vector<double>(grid_));
    rms_.assign(n, 0.0);
    fft_.SetFlag(Eigen::FFT<double>::HalfSpectrum);
    fft_.SetFlag(Eigen::FFT<double>::Unscaled);
    if (options.evaluation == Evaluation::direct) {
      cos_table_.resize(grid_);
      sin_table_.resize(grid_);
      for (std::uint32_t m = 0; m < grid_; ++m) {
        cos_table_[m] = std::cos(2.0 * std::numbers::pi * m / grid_);
        sin_table_[m] = std::sin(2.0 * std::numbers::pi * m / grid_);
      }
    }
  }

  std::uint32_t grid() const { return grid_; }
  Eigen::VectorXd start() const {
    return Eigen::Map<const Eigen::VectorXd>(start_.data(),
                                             static_cast<Eigen::Index>(start_.size()));
  }

  // Snow scale β_c = √(2ρP_c / (1 + ‖w_c‖²)).
  double snow_scale(std::size_t c, const Eigen::VectorXd& v, double& norm2) const {
    norm2 = 0.0;
    for (const SnowTerm& s : channels_[c].snow)
      norm2 += v(s.var) * v(s.var) + v(s.var + 1) * v(s.var + 1);
    return std::sqrt(2.0 * options_.snow_power_fraction * channels_[c].band_power / (1.0 + norm2));
  }

  // Fills signals_, rms_ and cf_ for the variables v; returns the aggregate grid crest
  // factor (the worst channel's, or the channels' mean).
  double synthesize(const Eigen::VectorXd& v) {
    double worst = 0.0, sum = 0.0;
    cf_.assign(channels_.size(), 0.0);
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      const Channel& channel = channels_[c];
      double norm2 = 0.0;
      const double beta = channel.snow.empty() ? 0.0 : snow_scale(c, v, norm2);
      double power = channel.band_power;
      for (const SnowTerm& s : channel.snow) {
        const Complex coefficient = beta * Complex(v(s.var), v(s.var + 1));
        power += std::norm(coefficient) / 2.0;
      }
      rms_[c] = std::sqrt(power);
      if (options_.evaluation == Evaluation::fft) {
        for (const Term& t : channel.terms)
          spectrum_[t.index] = std::polar(t.amplitude / 2.0, v(t.var) + t.offset);
        for (const SnowTerm& s : channel.snow)
          spectrum_[s.index] = beta / 2.0 * Complex(v(s.var), v(s.var + 1));
        fft_.inv(signals_[c].data(), spectrum_.data(), grid_);
        for (const Term& t : channel.terms) spectrum_[t.index] = 0.0;
        for (const SnowTerm& s : channel.snow) spectrum_[s.index] = 0.0;
      } else {
        auto& x = signals_[c];
        std::fill(x.begin(), x.end(), 0.0);
        auto add = [&](std::uint32_t index, Complex coefficient) {
          std::uint64_t position = 0;
          for (std::uint32_t m = 0; m < grid_; ++m) {
            x[m] += coefficient.real() * cos_table_[position] -
                    coefficient.imag() * sin_table_[position];
            position += index;
            if (position >= grid_) position -= grid_;
          }
        };
        for (const Term& t : channel.terms)
          add(t.index, std::polar(t.amplitude, v(t.var) + t.offset));
        for (const SnowTerm& s : channel.snow) add(s.index, beta * Complex(v(s.var), v(s.var + 1)));
      }
      double peak = 0.0;
      for (double value : signals_[c]) peak = std::max(peak, std::abs(value));
      cf_[c] = peak / rms_[c];
      worst = std::max(worst, cf_[c]);
      sum += cf_[c];
    }
    return mean_ ? sum / static_cast<double>(channels_.size()) : worst;
  }

  // F (GuillaumeOptions::aggregate) and its gradient.
  double evaluate(const Eigen::VectorXd& v, Eigen::VectorXd& gradient, const PowerKernel& kernel) {
    ++evaluations_;
    const double aggregate = synthesize(v);
    if (aggregate < best_cf_) {
      best_cf_ = aggregate;
      best_ = v;
    }
    const double worst = *std::max_element(cf_.begin(), cf_.end());
    const double p = kernel.p;
    const auto channel_count = static_cast<double>(channels_.size());
    std::vector<double>& sums = sums_;
    sums.assign(channels_.size(), 0.0);
    double total = 0.0;
    // Overwrite each signal with h = |z|^(p−1) sign(z), z = x / (rms · s_c) ∈ [−1, 1], s_c the
    // worst crest factor (worst) or the channel's own (mean), so no power overflows.
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      const double scale = 1.0 / (rms_[c] * (mean_ ? cf_[c] : worst));
      double sum = 0.0;
      for (double& value : signals_[c]) {
        double power = 0.0;
        value = kernel(value * scale, power);
        sum += power;
      }
      sums[c] = sum / grid_;
      total += sums[c];
    }
    double value = std::log(worst) + std::log(total) / p;
    if (mean_) {
      value = 0.0;
      for (std::size_t c = 0; c < channels_.size(); ++c)
        value += (std::log(cf_[c]) + std::log(sums[c]) / p) / channel_count;
    }

    gradient.setZero(v.size());
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      const Channel& channel = channels_[c];
      // ∂F/∂x_c(m) = κ_c h_c(m).
      const double kappa = mean_ ? 1.0 / (channel_count * grid_ * sums[c] * cf_[c] * rms_[c])
                                 : 1.0 / (grid_ * total * worst * rms_[c]);
      const double share = 1.0 / channel_count;            // of F per channel (mean)
      auto weight = [&](std::uint32_t index) -> Complex {  // W = κ Σ_m h(m) e^{+jθm}
        if (options_.evaluation == Evaluation::fft)
          return kappa * std::conj(gradient_spectrum_[index]);
        double re = 0.0;
        double im = 0.0;
        std::uint64_t position = 0;
        const auto& h = signals_[c];
        for (std::uint32_t m = 0; m < grid_; ++m) {
          re += h[m] * cos_table_[position];
          im += h[m] * sin_table_[position];
          position += index;
          if (position >= grid_) position -= grid_;
        }
        return kappa * Complex(re, im);
      };
      if (options_.evaluation == Evaluation::fft) {
        fft_.fwd(gradient_spectrum_.data(), signals_[c].data(), grid_);
      }
      for (const Term& t : channel.terms) {
        const Complex coefficient = std::polar(t.amplitude, v(t.var) + t.offset);
        gradient(t.var) -= (coefficient * weight(t.index)).imag();
      }
      if (channel.snow.empty()) continue;
      double norm2 = 0.0;
      const double beta = snow_scale(c, v, norm2);
      const double mu =
          mean_ ? share / rms_[c] / (2.0 * rms_[c]) : sums[c] / (total * rms_[c]) / (2.0 * rms_[c]);
      double g_dot_w = 0.0;
      std::vector<double>& g = snow_gradient_;
      g.assign(2 * channel.snow.size(), 0.0);
      for (std::size_t k = 0; k < channel.snow.size(); ++k) {
        const SnowTerm& s = channel.snow[k];
        const Complex w = weight(s.index);
        const Complex coefficient = beta * Complex(v(s.var), v(s.var + 1));
        g[2 * k] = w.real() - mu * coefficient.real();
        g[2 * k + 1] = -w.imag() - mu * coefficient.imag();
        g_dot_w += g[2 * k] * v(s.var) + g[2 * k + 1] * v(s.var + 1);
      }
      for (std::size_t k = 0; k < channel.snow.size(); ++k) {
        const SnowTerm& s = channel.snow[k];
        gradient(s.var) += beta * (g[2 * k] - v(s.var) * g_dot_w / (1.0 + norm2));
        gradient(s.var + 1) += beta * (g[2 * k + 1] - v(s.var + 1) * g_dot_w / (1.0 + norm2));
      }
    }
    if (held_from_ < gradient.size()) gradient.tail(gradient.size() - held_from_).setZero();
    return value;
  }

  // Per-channel grid crest factors and snow fractions of v.
  void channel_measures(const Eigen::VectorXd& v, std::vector<double>& cf,
                        std::vector<double>& snow) {
    synthesize(v);
    cf.assign(channels_.size(), 0.0);
    snow.assign(channels_.size(), 0.0);
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      double peak = 0.0;
      for (double value : signals_[c]) peak = std::max(peak, std::abs(value));
      cf[c] = peak / rms_[c];
      snow[c] = rms_[c] * rms_[c] / channels_[c].band_power - 1.0;
    }
  }

  MultisineSet to_set(const Eigen::VectorXd& v) const {
    MultisineSet result = set_;
    Eigen::Index var = 0;
    for (auto& lines : result.channels) {
      for (Line& line : lines) line.phase = std::remainder(v(var++), 2.0 * std::numbers::pi);
    }
    for (auto& source : result.shared) {
      for (Line& line : source.lines) line.phase = std::remainder(v(var++), 2.0 * std::numbers::pi);
    }
    if (!use_snow_) return result;
    for (std::size_t c = 0; c < channels_.size(); ++c) {
      double norm2 = 0.0;
      const double beta = snow_scale(c, v, norm2);
      std::vector<std::uint32_t> unused;
      for (const SnowTerm& s : channels_[c].snow) {
        const Complex coefficient = beta * Complex(v(s.var), v(s.var + 1));
        if (std::abs(coefficient) > 1e-9 * std::sqrt(channels_[c].band_power)) {
          result.channels[c].push_back({s.index, std::abs(coefficient), std::arg(coefficient)});
        } else {
          unused.push_back(s.index);
        }
      }
      std::sort(result.channels[c].begin(), result.channels[c].end(),
                [](const Line& a, const Line& b) { return a.index < b.index; });
      result.snow[c] = unused;
    }
    return result;
  }

  const Eigen::VectorXd& best() const { return best_; }
  int evaluations() const { return evaluations_; }

 private:
  const MultisineSet& set_;
  const GuillaumeOptions& options_;
  std::vector<Channel> channels_;
  std::vector<double> start_;
  bool use_snow_ = false;
  std::uint32_t grid_ = 0;
  Eigen::FFT<double> fft_;
  std::vector<Complex> spectrum_;
  std::vector<Complex> gradient_spectrum_;
  std::vector<std::vector<double>> signals_;
  std::vector<double> rms_;
  std::vector<double> sums_;
  std::vector<double> snow_gradient_;
  std::vector<double> cos_table_;
  std::vector<double> sin_table_;
  std::vector<double> cf_;  // per channel, of the last synthesis
  bool mean_ = false;       // ChannelAggregate::mean
  Eigen::Index held_from_;  // variables from here on are held at their start
  double best_cf_ = INFINITY;
  Eigen::VectorXd best_;
  int evaluations_ = 0;
};

void check_options(const GuillaumeOptions& options) {
  if (options.norms.empty())
    throw std::invalid_argument("guillaume: norms = {} (none), expected at least one p");
  double previous = 0.0;
  for (std::size_t k = 0; k < options.norms.size(); ++k) {
    const double p = options.norms[k];
    if (!(p >= 2.0) || !std::isfinite(p) || p <= previous) {
      throw std::invalid_argument("guillaume: norms[" + std::to_string(k) + "] = " +
                                  std::to_string(p) + ", expected finite, >= 2 and increasing");
    }
    previous = p;
  }
  if (!(options.snow_power_fraction >= 0.0 && options.snow_power_fraction <= 1.0)) {
    throw std::invalid_argument(
        "guillaume: snow_power_fraction = " + std::to_string(options.snow_power_fraction) +
        ", expected within [0, 1]");
  }
  if (options.starts.empty())
    throw std::invalid_argument("guillaume: starts = {} (none), expected at least one");
  if (options.iterations_per_norm < 1) {
    throw std::invalid_argument("guillaume: iterations_per_norm = " +
                                std::to_string(options.iterations_per_norm) + ", expected >= 1");
  }
}

// All channels together (coupled through shared sources, or a single channel).
// Variables at or past `held_from` (in the objective's order: own lines channel by channel,
// then shared lines, then snow) are held at their start.
MultisineSet optimise_jointly(const MultisineSet& start, const GuillaumeOptions& options,
                              GuillaumeReport* report,
                              Eigen::Index held_from = std::numeric_limits<Eigen::Index>::max()) {
  // Low p shapes the signal as a whole and is run on a coarse grid; the high p that set the
  // peak run on the fine grid, which also judges every iterate (the best is kept).
  CrestObjective objective(start, options, options.oversampling, held_from);
  CrestObjective coarse(start, options, std::max<std::uint32_t>(options.coarse_oversampling, 1),
                        held_from);
  Eigen::VectorXd v = objective.start();
  Eigen::VectorXd gradient(v.size());
  objective.evaluate(v, gradient, PowerKernel(options.norms.front()));  // the start is a candidate
  if (report != nullptr) {
    std::vector<double> unused;
    objective.channel_measures(v, report->cf_start, unused);
  }
  LbfgsOptions lbfgs;
  lbfgs.max_iterations = options.iterations_per_norm;
  for (double p : options.norms) {
    const PowerKernel kernel(p);
    CrestObjective& stage =
        p <= options.coarse_until_norm && coarse.grid() < objective.grid() ? coarse : objective;
    const Objective f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
      return stage.evaluate(x, g, kernel);
    };
    lbfgs_minimise(f, v, lbfgs);
  }
  Eigen::VectorXd best = objective.best();
  if (report != nullptr) {
    report->grid = objective.grid();
    report->evaluations = objective.evaluations() + coarse.evaluations();
    objective.channel_measures(best, report->cf_final, report->snow_fraction);
  }
  return objective.to_set(best);
}

double aggregate_of(const std::vector<double>& cf, ChannelAggregate aggregate) {
  double worst = 0.0, sum = 0.0;
  for (const double v : cf) {
    worst = std::max(worst, v);
    sum += v;
  }
  return aggregate == ChannelAggregate::mean ? sum / static_cast<double>(cf.size()) : worst;
}

// Each channel's own lines optimised for its own crest factor, the shared lines it carries
// held (GuillaumeOptions::polish_own_lines). Never worse for any channel (best iterate).
MultisineSet polish_own_lines(const MultisineSet& set, const GuillaumeOptions& options) {
  MultisineSet out = set;
  GuillaumeOptions one_channel = options;
  one_channel.snow_power_fraction = 0.0;  // snow the joint run used is now own lines
  one_channel.aggregate = ChannelAggregate::worst;
  for (std::size_t c = 0; c < set.channels.size(); ++c) {
    MultisineSet one;
    one.period = set.period;
    one.channels = {set.channels[c]};
    one.snow = {{}};
    const auto own = static_cast<Eigen::Index>(set.channels[c].size());
    for (const SharedSource& source : set.shared) {
      const double d = source.direction[c];
      if (d == 0.0) continue;
      for (const Line& line : source.lines) {
        one.channels[0].push_back({line.index, std::abs(d) * line.amplitude,
                                   line.phase + (d < 0.0 ? std::numbers::pi : 0.0)});
      }
    }
    const MultisineSet polished = optimise_jointly(one, one_channel, nullptr, own);
    std::copy_n(polished.channels[0].begin(), own, out.channels[c].begin());
  }
  return out;
}

// Channels coupled by shared sources: every start of options.starts optimised jointly, the
// best end by the aggregate kept, then (options.polish_own_lines) each channel's own lines.
MultisineSet optimise_coupled(const MultisineSet& start, const GuillaumeOptions& options,
                              GuillaumeReport* report) {
  MultisineSet best;
  GuillaumeReport best_report;
  double best_aggregate = INFINITY;
  std::vector<std::vector<double>> cf_by_start;
  std::vector<double> cf_given;
  std::size_t best_start = 0;
  int evaluations = 0;
  for (std::size_t k = 0; k < options.starts.size(); ++k) {
    GuillaumeReport part;
    MultisineSet result =
        optimise_jointly(with_start_phases(start, options.starts[k], k), options, &part);
    evaluations += part.evaluations;
    if (k == 0) cf_given = part.cf_start;
    cf_by_start.push_back(part.cf_final);
    const double aggregate = aggregate_of(part.cf_final, options.aggregate);
    if (aggregate < best_aggregate) {
      best_aggregate = aggregate;
      best = std::move(result);
      best_report = std::move(part);
      best_start = k;
    }
  }
  if (options.polish_own_lines) best = polish_own_lines(best, options);
  if (report != nullptr) {
    *report = best_report;
    report->cf_start = cf_given;
    report->evaluations = evaluations;
    report->cf_by_start = std::move(cf_by_start);
    report->best_start = best_start;
    if (options.polish_own_lines) {
      GuillaumeOptions measure = options;
      measure.snow_power_fraction = 0.0;
      CrestObjective objective(best, measure, options.oversampling,
                               std::numeric_limits<Eigen::Index>::max());
      std::vector<double> unused;
      objective.channel_measures(objective.start(), report->cf_final, unused);
    }
  }
  return best;
}

}  // namespace

MultisineSet guillaume(const MultisineSet& start, const GuillaumeOptions& options,
                       GuillaumeReport* report) {
  validate_set(start);
  check_options(options);
  if (!start.shared.empty()) return optimise_coupled(start, options, report);
  if (start.channels.size() == 1) return optimise_jointly(start, options, report);
  // Without shared sources the channels do not interact: the worst channel's crest factor
  // is least when every channel's is, so each is optimised on its own.
  MultisineSet result = start;
  if (report != nullptr) *report = GuillaumeReport{};
  for (std::size_t c = 0; c < start.channels.size(); ++c) {
    MultisineSet one;
    one.period = start.period;
    one.channels = {start.channels[c]};
    one.snow = {start.snow.empty() ? std::vector<std::uint32_t>{} : start.snow[c]};
    GuillaumeReport part;
    MultisineSet optimised = optimise_jointly(one, options, &part);
    result.channels[c] = std::move(optimised.channels.front());
    if (!result.snow.empty()) result.snow[c] = std::move(optimised.snow.front());
    if (report != nullptr) {
      report->grid = std::max(report->grid, part.grid);
      report->evaluations += part.evaluations;
      report->cf_start.push_back(part.cf_start.front());
      report->cf_final.push_back(part.cf_final.front());
      report->snow_fraction.push_back(part.snow_fraction.front());
    }
  }
  return result;
}

std::vector<Line> guillaume(std::span<const Line> start, std::uint32_t period,
                            const GuillaumeOptions& options, GuillaumeReport* report) {
  MultisineSet set;
  set.period = period;
  set.channels.emplace_back(start.begin(), start.end());
  set.snow.emplace_back();
  return guillaume(set, options, report).channels.front();
}

}  // namespace excite::host::multisine
