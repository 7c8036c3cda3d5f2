// SPDX-License-Identifier: MIT
#include "sim/lti/parse_element.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>
#include <sstream>

#include "base/config/document.hpp"

namespace excite::sim {
namespace {

// Recursive-descent parser over one element string. Each parse_* method consumes what it
// recognises and throws with the current position otherwise.
class Parser {
 public:
  Parser(std::string_view text, std::string_view context, const ElementRules& rules)
      : text_(text), context_(context), rules_(rules) {}

  Element parse() {
    std::vector<Term> terms;
    skip_space();
    if (at_end()) fail("expected an element (use \"0\" for no coupling)");
    double sign = 1.0;
    if (peek() == '+' || peek() == '-') {
      sign = take() == '-' ? -1.0 : 1.0;
    }
    while (true) {
      const std::size_t start = pos_;
      Term t = parse_term();
      t.gain *= sign;
      const std::string problem = check_term(t, rules_);
      if (!problem.empty()) fail_at(start, problem);
      if (t.gain != 0.0) terms.push_back(std::move(t));
      skip_space();
      if (at_end()) break;
      if (peek() != '+' && peek() != '-') fail("expected '+', '-' or the end of the element");
      sign = take() == '-' ? -1.0 : 1.0;
    }
    return Element(std::move(terms), std::string(text_));
  }

 private:
  Term parse_term() {
    Term t;
    t.gain = 1.0;
    std::optional<double> delay;
    skip_space();
    if (!starts_item()) fail("expected a number, 's', '(' or a delay e^-τs");
    parse_product(t.gain, t.zeros, delay);
    skip_space();
    while (!at_end() && peek() == '/') {
      take();
      skip_space();
      if (!starts_item()) fail("expected a denominator after '/': a number or '(' … ')'");
      double divisor = 1.0;
      in_denominator_ = true;
      parse_product(divisor, t.poles, delay);
      in_denominator_ = false;
      if (divisor == 0.0) fail("division by zero");
      t.gain /= divisor;
      skip_space();
    }
    t.delay_min = delay.value_or(0.0);
    return t;
  }

  bool starts_item() const {
    if (at_end()) return false;
    const char c = peek();
    return std::isdigit(static_cast<unsigned char>(c)) != 0 || c == '.' || c == 's' || c == '(' ||
           c == 'e';
  }

  // item { ['*'] item }: numbers multiply `gain`, polynomial factors go to `factors`.
  void parse_product(double& gain, std::vector<Factor>& factors, std::optional<double>& delay) {
    parse_item(gain, factors, delay);
    while (true) {
      skip_space();
      if (!at_end() && peek() == '*') {
        take();
        skip_space();
        if (!starts_item()) fail("expected a factor after '*'");
      }
      if (!starts_item()) return;
      parse_item(gain, factors, delay);
    }
  }

  void parse_item(double& gain, std::vector<Factor>& factors, std::optional<double>& delay) {
    const char c = peek();
    if (c == 'e') {
      const std::size_t start = pos_;
      const double d = parse_delay();
      if (delay) fail_at(start, "a term may have only one delay");
      // "K/(τs+1) e^-θs" multiplies by the delay; inside the denominator's parentheses the
      // delay would divide (a prediction).
      if (paren_depth_ > 0 && in_denominator_) {
        fail_at(start, "a delay inside the denominator's parentheses; write it in the numerator");
      }
      delay = d;
      return;
    }
    if (c == 's') {
      take();
      factors.push_back({{0.0, 1.0}, parse_power()});
      return;
    }
    if (c == '(') {
      take();
      skip_space();
      if (!at_end() && peek() == '(') {
        // A parenthesised product such as ((33s+1)(8.3s+1)).
        double inner_gain = 1.0;
        std::vector<Factor> inner;
        const bool had_delay = delay.has_value();
        ++paren_depth_;
        parse_product(inner_gain, inner, delay);
        --paren_depth_;
        expect(')');
        const std::size_t power_at = pos_;
        const int power = parse_power();
        if (power > 1 && !had_delay && delay) {
          fail_at(power_at, "a power of a group holding a delay; write the delay once, outside");
        }
        gain *= std::pow(inner_gain, power);
        for (Factor& f : inner) {
          f.power *= power;
          factors.push_back(std::move(f));
        }
        return;
      }
      const std::size_t start = pos_;
      Polynomial p = parse_polynomial();
      expect(')');
      const int power = parse_power();
      if (degree(p) < 0) fail_at(start, "factor is the zero polynomial");
      if (degree(p) == 0) {
        gain *= std::pow(p[0], power);
      } else {
        factors.push_back({std::move(p), power});
      }
      return;
    }
    gain *= parse_number();
  }

  // Optional '^' integer (1…16) after a factor.
  int parse_power() {
    skip_space();
    if (at_end() || peek() != '^') return 1;
    take();
    skip_space();
    const std::size_t start = pos_;
    int value = 0;
    while (!at_end() && std::isdigit(static_cast<unsigned char>(peek())) != 0) {
      value = value * 10 + (take() - '0');
      if (value > 16) fail_at(start, "expected a power from 1 to 16");
    }
    if (pos_ == start || value < 1) fail_at(start, "expected a power from 1 to 16");
    return value;
  }

  Polynomial parse_polynomial() {
    Polynomial p;
    skip_space();
    double sign = 1.0;
    if (!at_end() && (peek() == '+' || peek() == '-')) sign = take() == '-' ? -1.0 : 1.0;
    while (true) {
      skip_space();
      double coeff = 1.0;
      bool has_number = false;
      if (!at_end() && (std::isdigit(static_cast<unsigned char>(peek())) != 0 || peek() == '.')) {
        coeff = parse_number();
        has_number = true;
        skip_space();
        if (!at_end() && peek() == '*') {
          take();
          skip_space();
          if (at_end() || peek() != 's') fail("expected 's' after '*' in a polynomial");
        }
      }
      std::size_t power = 0;
      if (!at_end() && peek() == 's') {
        take();
        power = static_cast<std::size_t>(parse_power());
      } else if (!has_number) {
        fail("expected a coefficient or 's' in the polynomial");
      }
      if (p.size() <= power) p.resize(power + 1, 0.0);
      p[power] += sign * coeff;
      skip_space();
      if (at_end() || (peek() != '+' && peek() != '-')) return p;
      sign = take() == '-' ? -1.0 : 1.0;
    }
  }

  // e^-τs, e^{-τs}, e^(-τs), exp(-τs); τ defaults to 1. Returns τ in minutes.
  double parse_delay() {
    const std::size_t start = pos_;
    char close = '\0';
    if (text_.substr(pos_, 4) == "exp(") {
      pos_ += 4;
      close = ')';
    } else if (text_.substr(pos_, 2) == "e^") {
      pos_ += 2;
      skip_space();
      if (!at_end() && (peek() == '{' || peek() == '(')) close = take() == '{' ? '}' : ')';
    } else {
      fail_at(start, "expected a delay written e^-τs");
    }
    skip_space();
    if (at_end() || peek() != '-') {
      fail(
          "expected '-' in the delay e^-τs (a delay τ ≥ 0 minutes; a positive exponent "
          "would be a prediction)");
    }
    take();
    skip_space();
    double tau = 1.0;
    if (!at_end() && (std::isdigit(static_cast<unsigned char>(peek())) != 0 || peek() == '.')) {
      tau = parse_number();
      skip_space();
      if (!at_end() && peek() == '*') {
        take();
        skip_space();
      }
    }
    if (at_end() || peek() != 's') fail("expected 's' to close the delay exponent -τs");
    take();
    if (close != '\0') expect(close);
    return tau;
  }

  double parse_number() {
    skip_space();
    const std::size_t start = pos_;
    std::size_t end = pos_;
    auto digit_at = [&](std::size_t i) {
      return i < text_.size() && std::isdigit(static_cast<unsigned char>(text_[i])) != 0;
    };
    while (digit_at(end)) ++end;
    if (end < text_.size() && text_[end] == '.') {
      ++end;
      while (digit_at(end)) ++end;
    }
    if (end == start || (end == start + 1 && text_[start] == '.')) {
      fail("expected a number");
    }
    // An exponent only when 'e' is followed by digits: "4.09e^-1.3s" is a gain and a delay.
    if (end < text_.size() && (text_[end] == 'e' || text_[end] == 'E')) {
      std::size_t k = end + 1;
      if (k < text_.size() && (text_[k] == '+' || text_[k] == '-')) ++k;
      if (digit_at(k)) {
        end = k;
        while (digit_at(end)) ++end;
      }
    }
    double value = 0.0;
    const auto [ptr, ec] = std::from_chars(text_.data() + start, text_.data() + end, value);
    if (ec != std::errc{} || ptr != text_.data() + end || !std::isfinite(value)) {
      fail_at(start, "number out of range");
    }
    pos_ = end;
    return value;
  }

  void expect(char c) {
    skip_space();
    if (at_end() || peek() != c) fail(std::string("expected '") + c + "'");
    take();
  }

  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(peek())) != 0) ++pos_;
  }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return text_[pos_]; }
  char take() { return text_[pos_++]; }

  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::size_t at, const std::string& what) const {
    std::ostringstream os;
    os << context_ << ": cannot use \"" << text_ << "\" at position " << at + 1;
    if (at < text_.size()) {
      os << " ('" << text_[at] << "')";
    } else {
      os << " (end of text)";
    }
    os << ": " << what;
    throw ElementSyntaxError(os.str(), at);
  }

  std::string_view text_;
  std::string_view context_;
  const ElementRules& rules_;
  std::size_t pos_ = 0;
  bool in_denominator_ = false;  // parsing the items after a '/'
  int paren_depth_ = 0;          // nesting of parenthesised products
};

std::string describe(const Polynomial& p) {
  std::ostringstream os;
  bool first = true;
  for (std::size_t i = p.size(); i > 0; --i) {
    const double c = p[i - 1];
    if (c == 0.0) continue;
    if (!first) os << (c < 0 ? " - " : " + ");
    if (first && c < 0) os << '-';
    const double a = std::abs(c);
    const std::size_t power = i - 1;
    if (a != 1.0 || power == 0) os << config::format_number(a);
    if (power >= 1) os << 's';
    if (power >= 2) os << '^' << power;
    first = false;
  }
  return first ? "0" : os.str();
}

}  // namespace

std::string check_term(const Term& term, const ElementRules& rules) {
  if (!std::isfinite(term.gain))
    return "gain " + config::format_number(term.gain) + " is not finite";
  if (!std::isfinite(term.delay_min) || term.delay_min < 0.0) {
    return "delay " + config::format_number(term.delay_min) + " min, expected a finite delay ≥ 0";
  }
  for (const auto* list : {&term.zeros, &term.poles}) {
    for (const Factor& f : *list) {
      if (f.power < 1) return "factor power " + std::to_string(f.power) + ", expected ≥ 1";
      for (double c : f.poly) {
        if (!std::isfinite(c))
          return "factor (" + describe(f.poly) + ") has a non-finite coefficient";
      }
      if (degree(f.poly) < 0) return "a factor is the zero polynomial";
    }
  }
  if (term.numerator_degree() > term.denominator_degree()) {
    return "improper term: numerator degree " + std::to_string(term.numerator_degree()) +
           " exceeds denominator degree " + std::to_string(term.denominator_degree()) +
           " (expected a proper transfer function)";
  }
  if (!rules.allow_unstable) {
    for (const Factor& f : term.poles) {
      for (const std::complex<double>& p : roots(f.poly)) {
        if (p.real() >= 0.0) {
          std::string msg = "pole at s = " + config::format_number(p.real() + 0.0);  // no "-0"
          if (p.imag() != 0.0)
            msg += (p.imag() > 0 ? " + " : " - ") + config::format_number(std::abs(p.imag())) + "j";
          msg += " 1/min from factor (" + describe(f.poly) + ")";
          if (degree(f.poly) == 1 && f.poly[0] != 0.0) {
            msg += ", time constant " + config::format_number(f.poly[1] / f.poly[0]) + " min";
          }
          return msg +
                 ", expected poles in the open left half-plane (time constants > 0); "
                 "set allow_unstable to accept";
        }
      }
    }
  }
  return "";
}

Element parse_element(std::string_view text, std::string_view context, const ElementRules& rules) {
  return Parser(text, context, rules).parse();
}

}  // namespace excite::sim
