// SPDX-License-Identifier: MIT
#pragma once
// The element grammar: how one entry of a transfer-function matrix is written in code,
// in TOML plant files and in the library (one grammar, documented in sim/lti/README.md).
//
//   element  := [sign] term { sign term }            sign := '+' | '-'
//   term     := item { ['*'] item } { '/' item { ['*'] item } }
//   item     := number | 's' | '(' group ')' ['^' integer] | delay
//   group    := polynomial | item { ['*'] item }     (a product when it starts with '(')
//   polynomial := [sign] monomial { sign monomial }  monomial := number ['*'] ['s' ['^' integer]] |
//   's' ['^' integer] delay    := 'e^' ( '-' [number] ['*'] 's' | '{' … '}' | '(' … ')' ) | 'exp('
//   '-' [number] ['*'] 's' ')'
//
// Examples: "4.09 e^-1.3s / ((33s+1)(8.3s+1))", "14(10s+1) e^-0.02s / ((45s+1)(17.4s^2+3s+1))",
// "-0.56 e^-1s", "87.8/(194s+1) + 1.4/(15s+1)", "0". Time in minutes. At most one delay per
// term; each term must be proper; poles must lie in the open left half-plane unless
// ElementRules::allow_unstable.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

#include "sim/lti/element.hpp"

namespace excite::sim {

/// A malformed or rejected element. what() names the context (e.g. "G row 2 (y2), column 3
/// (u3)"), quotes the text, gives the 1-based character position and says what was expected.
class ElementSyntaxError : public std::invalid_argument {
 public:
  ElementSyntaxError(const std::string& message, std::size_t position)
      : std::invalid_argument(message), position_(position) {}
  /// 0-based offset into the text where the problem was found.
  std::size_t position() const { return position_; }

 private:
  std::size_t position_;
};

/// Parses one element. `context` names where the text came from, for error messages.
/// Throws ElementSyntaxError.
Element parse_element(std::string_view text, std::string_view context = "element",
                      const ElementRules& rules = {});

/// Checks a term built in code or parsed: finite coefficients, non-zero factors, proper,
/// delay ≥ 0, poles in the open left half-plane unless allowed. Returns "" when the term is
/// acceptable, else a description of the first problem.
std::string check_term(const Term& term, const ElementRules& rules = {});

}  // namespace excite::sim
