// SPDX-License-Identifier: MIT
#include "host/adaptive/cv_limit_text.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace excite::host {
namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

// "CV=LOW:HIGH" into the limits of the output named CV (deviations from its baseline).
void parse_limit(const std::string& text, const std::vector<std::string>& outputs,
                 const std::string& whose, CvLimits& limits) {
  const auto eq = text.rfind('=');
  const auto colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos) {
    throw std::invalid_argument("--limit \"" + text +
                                "\", expected CV=LOW:HIGH (deviations from the baseline), e.g. "
                                "xD=-0.01:0.01");
  }
  const std::string name = text.substr(0, eq);
  const auto at = std::find(outputs.begin(), outputs.end(), name);
  if (at == outputs.end()) {
    throw std::invalid_argument("--limit \"" + text + "\": CV \"" + name + "\", expected one of " +
                                whose + " outputs: " + joined(outputs));
  }
  const auto number = [&](const std::string& part) {
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(v)) {
      throw std::invalid_argument("--limit \"" + text + "\": \"" + part +
                                  "\", expected a finite number");
    }
    return v;
  };
  const auto j = at - outputs.begin();
  limits.low(j) = number(text.substr(eq + 1, colon - eq - 1));
  limits.high(j) = number(text.substr(colon + 1));
  // Reversed (1:-1), zero-width (0:0) or one-sided (0:1) limits leave the baseline no room.
  if (!(limits.low(j) < 0.0 && limits.high(j) > 0.0)) {
    throw std::invalid_argument("--limit \"" + text + "\": LOW:HIGH = " + text.substr(eq + 1) +
                                ", expected LOW < 0 < HIGH (deviations from the baseline, which "
                                "lies inside its limits)");
  }
}

}  // namespace

CvLimits parse_cv_limits(const std::vector<std::string>& texts,
                         const std::vector<std::string>& outputs, const std::string& whose) {
  CvLimits limits;
  constexpr double kUnlimited = std::numeric_limits<double>::infinity();  // a CV without --limit
  const auto n = static_cast<Eigen::Index>(outputs.size());
  limits.low = Eigen::VectorXd::Constant(n, -kUnlimited);
  limits.high = Eigen::VectorXd::Constant(n, kUnlimited);
  for (const std::string& text : texts) parse_limit(text, outputs, whose, limits);
  return limits;
}

}  // namespace excite::host
