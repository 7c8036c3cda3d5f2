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

// How an option of limits is worded: --limit for CVs (the outputs), --mv-limit for MVs.
struct LimitWords {
  const char* option;    // "--limit"
  const char* channel;   // "CV"
  const char* channels;  // "outputs"
  const char* example;   // "xD=-0.01:0.01"
};
constexpr LimitWords kCvWords{"--limit", "CV", "outputs", "xD=-0.01:0.01"};
constexpr LimitWords kMvWords{"--mv-limit", "MV", "inputs", "u1=-0.6:0.6"};

// "NAME=LOW:HIGH" into the limits of the channel NAME (deviations from its baseline).
void parse_limit(const std::string& text, const std::vector<std::string>& names,
                 const std::string& whose, const LimitWords& w, CvLimits& limits) {
  const std::string option = w.option;
  const std::string channel = w.channel;
  const auto eq = text.rfind('=');
  const auto colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos) {
    throw std::invalid_argument(option + " \"" + text + "\", expected " + channel +
                                "=LOW:HIGH (deviations from the baseline), e.g. " + w.example);
  }
  const std::string name = text.substr(0, eq);
  const auto at = std::find(names.begin(), names.end(), name);
  if (at == names.end()) {
    throw std::invalid_argument(option + " \"" + text + "\": " + channel + " \"" + name +
                                "\", expected one of " + whose + " " + w.channels + ": " +
                                joined(names));
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
      throw std::invalid_argument(option + " \"" + text + "\": \"" + part +
                                  "\", expected a finite number");
    }
    return v;
  };
  const auto j = at - names.begin();
  limits.low(j) = number(text.substr(eq + 1, colon - eq - 1));
  limits.high(j) = number(text.substr(colon + 1));
  // Reversed (1:-1), zero-width (0:0) or one-sided (0:1) limits leave the baseline no room.
  if (!(limits.low(j) < 0.0 && limits.high(j) > 0.0)) {
    throw std::invalid_argument(option + " \"" + text + "\": LOW:HIGH = " + text.substr(eq + 1) +
                                ", expected LOW < 0 < HIGH (deviations from the baseline, which "
                                "lies inside its limits)");
  }
}

// Every channel named in `texts` limited, the others unlimited (∓infinity).
CvLimits parse_limits(const std::vector<std::string>& texts, const std::vector<std::string>& names,
                      const std::string& whose, const LimitWords& words) {
  CvLimits limits;
  constexpr double kUnlimited = std::numeric_limits<double>::infinity();
  const auto n = static_cast<Eigen::Index>(names.size());
  limits.low = Eigen::VectorXd::Constant(n, -kUnlimited);
  limits.high = Eigen::VectorXd::Constant(n, kUnlimited);
  for (const std::string& text : texts) parse_limit(text, names, whose, words, limits);
  return limits;
}

}  // namespace

CvLimits parse_cv_limits(const std::vector<std::string>& texts,
                         const std::vector<std::string>& outputs, const std::string& whose) {
  return parse_limits(texts, outputs, whose, kCvWords);
}

CvLimits parse_mv_limits(const std::vector<std::string>& texts,
                         const std::vector<std::string>& inputs, const std::string& whose) {
  return parse_limits(texts, inputs, whose, kMvWords);
}

}  // namespace excite::host
