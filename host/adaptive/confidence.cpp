// SPDX-License-Identifier: MIT
#include "host/adaptive/confidence.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <boost/math/distributions/students_t.hpp>

namespace excite::host {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// "[2 4] 9.7 +- 12": the minor of rows and columns 2 and 4 (1-based), its 95 % half-width.
std::string minor_text(const PrincipalMinor& m, double z) {
  std::string text = "[";
  for (const int i : m.rows) text += (text.size() > 1 ? " " : "") + std::to_string(i + 1);
  char numbers[64];
  std::snprintf(numbers, sizeof numbers, "] %.3g +- %.2g", m.value, z * m.std_error);
  return text + numbers;
}

// The half-width of σ_i's interval that the criterion |σ̂ − σ| ≤ tol·σ allows at every σ
// inside it, over σ̂_i. The low end binds: σ = σ̂ − h meets it when h ≤ tol·(σ̂ − h), so
// h ≤ σ̂·tol/(1 + tol) (σ̂/6 for 20 %); the high end allows σ̂·tol/(1 − tol).
double allowed_sigma_half_width(double tolerance) {
  return tolerance / (1.0 + tolerance);
}

std::string ratio_text(const char* what, double need) {
  char text[120];
  std::snprintf(text, sizeof text, "%s at %.2f of its tolerance", what, need);
  return text;
}

// Why `now` does not agree with `before` (both with G(0) and its uncertainty); "" when it does.
std::string disagreement_with(const GainEvidence& now, const GainEvidence& before,
                              const StopRule& rule) {
  const GainUncertainty& a = *now.uncertainty;
  const GainUncertainty& b = *before.uncertainty;
  const Eigen::Index n = a.singular_values.size() - 1;
  if (b.singular_values.size() != a.singular_values.size())
    return "the earlier estimate's size differs";
  char text[200];
  const double jump = std::abs(a.singular_values(n) - b.singular_values(n));
  if (jump > rule.z * b.singular_value_se(n)) {
    std::snprintf(text, sizeof text,
                  "sigma_n moved %.4g since the earlier estimate, beyond its 95 %% half-width %.4g",
                  jump, rule.z * b.singular_value_se(n));
    return text;
  }
  const Eigen::VectorXd v = now.gain->input_directions.col(n);
  const Eigen::VectorXd w = before.gain->input_directions.col(n);
  const double cosine = std::min(1.0, std::abs(v.dot(w)) / (v.norm() * w.norm()));
  const double angle = std::acos(cosine) * 180.0 / std::numbers::pi;
  if (angle > rule.z * b.input_angle_se_deg(n)) {
    std::snprintf(text, sizeof text,
                  "v_n turned %.3g deg since the earlier estimate, beyond its 95 %% angle %.3g deg",
                  angle, rule.z * b.input_angle_se_deg(n));
    return text;
  }
  for (std::size_t i = 0; i < a.principal_minors.size() && i < b.principal_minors.size(); ++i) {
    if (std::signbit(a.principal_minors[i].value) != std::signbit(b.principal_minors[i].value))
      return "a principal minor changed sign since the earlier estimate";
  }
  return "";
}

// The residual tests that fail over the outputs (none without fits), each named in `failed`
// as " y1 not white;" or " y1 correlated with u2;".
int failed_residual_tests(const GainEvidence& now, std::string& failed) {
  int count = 0;
  const std::size_t outputs = now.fits != nullptr ? now.fits->size() : 0;
  for (std::size_t o = 0; o < outputs; ++o) {
    const ResidualTests& t = (*now.fits)[o].residual_tests;
    if (t.lags == 0) continue;  // not computed (a constant output)
    if (!t.white()) {
      ++count;
      failed += " y" + std::to_string(o + 1) + " not white;";
    }
    for (Eigen::Index i = 0; i < t.independence.size(); ++i) {
      if (!t.independent_of(i)) {
        ++count;
        failed += " y" + std::to_string(o + 1) + " correlated with u" + std::to_string(i + 1) + ";";
      }
    }
  }
  return count;
}

// The fewest degrees of freedom of any output's noise level (OutputFit); +∞ without fits.
double fewest_noise_level_dof(const GainEvidence& now) {
  double dof = std::numeric_limits<double>::infinity();
  if (now.fits == nullptr) return dof;
  for (const OutputFit& f : *now.fits) dof = std::min(dof, f.noise_level_dof);
  return dof;
}

}  // namespace

double rule_quantile(double z, double dof) {
  if (std::isinf(dof) && dof > 0.0) return z;
  const double coverage = 0.5 * std::erfc(-z / std::numbers::sqrt2);  // Φ(z)
  return boost::math::quantile(boost::math::students_t(std::max(dof, 1.0)), coverage);
}

Confidence confidence_of(const GainEvidence& now, const GainEvidence* previous,
                         const StopRule& rule) {
  Confidence c;
  c.sigma_n_need = c.angle_need = c.minor_need = c.need = kNaN;
  c.noise_level_dof = fewest_noise_level_dof(now);
  c.z = rule_quantile(rule.z, c.noise_level_dof);
  if (now.gain == nullptr || now.uncertainty == nullptr) {
    c.missing = now.unavailable.empty() ? "no G(0) uncertainty (a gain not estimated or on a bound)"
                                        : now.unavailable;
    return c;
  }
  const GainUncertainty& u = *now.uncertainty;
  const Eigen::Index r = u.singular_values.size();
  const double z = c.z;
  // The weights' yardstick (direction_weights): each part over its tolerance as stated, σ_i's
  // over 0.2·σ̂_i; only their ratios matter. The stop reads σ_n exactly (below).
  c.direction_need.resize(r);
  for (Eigen::Index i = 0; i < r; ++i) {
    const double sigma =
        rule.z * u.singular_value_se(i) / (rule.sigma_tolerance * std::abs(u.singular_values(i)));
    const double angle = rule.z * u.input_angle_se_deg(i) / rule.angle_tolerance_deg;
    c.direction_need(i) = std::max(sigma, angle);
  }
  if (!c.direction_need.allFinite()) {
    c.direction_need.setConstant(kNaN);
    c.missing = "the G(0) uncertainty is not finite";
    return c;
  }
  c.gain_identified = true;
  c.sigma_n_need =
      z * u.singular_value_se(r - 1) /
      (allowed_sigma_half_width(rule.sigma_tolerance) * std::abs(u.singular_values(r - 1)));
  c.angle_need = z * u.input_angle_se_deg(r - 1) / rule.angle_tolerance_deg;
  c.minor_need = 0.0;
  std::string uncertain_minors;
  for (const PrincipalMinor& m : u.principal_minors) {
    const double need = z * m.std_error / std::abs(m.value);
    c.minor_need = std::max(c.minor_need, std::isnan(need) ? 1e300 : need);
    if (!(std::abs(m.value) >= z * m.std_error)) {
      ++c.sign_uncertain_minors;
      uncertain_minors += (uncertain_minors.empty() ? ": " : ", ") + minor_text(m, z);
    }
  }
  c.need = std::max({c.sigma_n_need, c.angle_need, c.minor_need});
  std::string failed;
  c.failed_residual_tests = failed_residual_tests(now, failed);
  std::string disagreement;
  if (previous != nullptr && previous->gain != nullptr && previous->uncertainty != nullptr) {
    c.has_previous = true;
    disagreement = disagreement_with(now, *previous, rule);
    c.agrees = disagreement.empty();
  }
  c.met = c.need <= 1.0 && c.agrees && !(rule.residual_tests && c.failed_residual_tests > 0);
  std::string missing;
  const auto add = [&](const std::string& part) {
    missing += (missing.empty() ? "" : "; ") + part;
  };
  if (c.sigma_n_need > 1.0) add(ratio_text("sigma_n's 95 % half-width", c.sigma_n_need));
  if (c.angle_need > 1.0) add(ratio_text("v_n's 95 % angle", c.angle_need));
  if (c.sign_uncertain_minors > 0) {
    add(std::to_string(c.sign_uncertain_minors) + " principal minor(s) of uncertain sign" +
        uncertain_minors);
  }
  if (c.need > 1.0 && z != rule.z) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "(95 %% read as +-%.2f SE: Student's t at %.1f degrees of freedom of the noise "
                  "model's low-frequency level)",
                  z, c.noise_level_dof);
    missing += std::string(missing.empty() ? "" : " ") + text;
  }
  if (!c.has_previous) add("no earlier estimate to agree with");
  if (!disagreement.empty()) add(disagreement);
  if (rule.residual_tests && c.failed_residual_tests > 0) {
    failed.pop_back();
    add("residual tests failed (1 %):" + failed);
  }
  c.missing = missing;
  return c;
}

Eigen::VectorXd direction_weights(const Confidence& confidence, int directions, double floor) {
  if (!(floor > 0.0 && floor <= 1.0)) {
    throw std::invalid_argument("direction weight floor = " + std::to_string(floor) +
                                ", expected 0 < floor <= 1");
  }
  Eigen::VectorXd w = Eigen::VectorXd::Ones(directions);
  if (!confidence.gain_identified || confidence.direction_need.size() != directions) return w;
  const double largest = confidence.direction_need.maxCoeff();
  if (!(largest > 0.0)) return w;
  for (int i = 0; i < directions; ++i)
    w(i) = std::max(floor, confidence.direction_need(i) / largest);
  return w;
}

std::optional<double> predicted_stop_min(const Confidence& confidence, double length_min) {
  if (!confidence.gain_identified || !std::isfinite(confidence.need)) return std::nullopt;
  return confidence.met ? length_min : length_min * confidence.need * confidence.need;
}

}  // namespace excite::host
