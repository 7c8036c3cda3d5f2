// SPDX-License-Identifier: MIT
#pragma once
// An HTML page (the Monte Carlo report's), written so that every string is HTML-escaped in
// one place (issue 40 §2: a design name from a shard's run.json once reached index.html as a
// script).
// What the page accepts decides what it is, at compile time:
//   - a string literal (or another constant expression) of this file's code: markup, as is;
//   - CodeMarkup{p}: markup the code owns that is not a constant (the shared style sheet);
//   - std::string: text, every & < > " ' escaped, whatever it came from;
//   - a number: its text.
// A `const char*` computed at run time (a ternary of two literals, a table's field) does not
// compile as markup: it must be said to be text (std::string) or CodeMarkup.

#include <concepts>
#include <sstream>
#include <string>
#include <type_traits>

namespace excite::host {

/// Markup fixed in the code: only a constant expression converts (consteval).
struct Markup {
  consteval Markup(const char* literal) : text(literal) {}  // NOLINT: implicit on purpose
  const char* text;
};

/// Markup the code owns that is not a constant expression; spelled out where used.
struct CodeMarkup {
  const char* text;
};

/// `text` with & < > " ' as character references.
std::string html_escaped(const std::string& text);

class HtmlPage {
 public:
  HtmlPage& operator<<(Markup m) {
    out_ << m.text;
    return *this;
  }
  HtmlPage& operator<<(CodeMarkup m) {
    out_ << m.text;
    return *this;
  }
  template <class T>
  requires std::same_as<std::remove_cvref_t<T>, std::string> HtmlPage& operator<<(const T& text) {
    out_ << html_escaped(text);
    return *this;
  }
  HtmlPage& operator<<(char c) { return *this << std::string(1, c); }
  template <class T>
  requires(std::is_arithmetic_v<T> && !std::same_as<T, char> && !std::same_as<T, bool>) HtmlPage&
  operator<<(T number) {
    out_ << number;
    return *this;
  }
  std::string str() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

}  // namespace excite::host
