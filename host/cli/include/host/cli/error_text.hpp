// SPDX-License-Identifier: MIT
#pragma once
// What `excite: error: …` prints (issue 40 §5), in one place:
//   - a message is printed with every control byte but the newline and the tab as \xNN, so
//     file contents quoted in it (a tag name, a CSV cell) cannot send escape sequences to
//     the terminal;
//   - a library's internal text (std::bad_alloc, "stoi": no sentence, no field) is replaced
//     by the one message form, saying what it means for the user.

#include <cstdio>
#include <exception>
#include <new>
#include <string>

namespace excite::host::cli {

/// `text` with every control byte except '\n' and '\t' (and 0x7f) written as \xNN.
inline std::string printable(const std::string& text) {
  std::string out;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte < 0x20 && c != '\n' && c != '\t') || byte == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", static_cast<unsigned>(byte));
      out += hex;
    } else {
      out += c;
    }
  }
  return out;
}

/// The message for an exception that reached main: its own text, or, for a library's
/// internal one, the one message form.
inline std::string error_text(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e) != nullptr) {
    return "memory = exhausted (" + std::string(e.what()) +
           "), expected an input the command can hold: a file or a count in it is too large "
           "for this machine";
  }
  const std::string what = e.what();
  if (what.find(' ') == std::string::npos) {  // "stoi", "vector::_M_range_check": no sentence
    return "internal check = " + what +
           ", expected a message naming the input: an input reached a check that does not "
           "name it (please report the command line)";
  }
  return what;
}

}  // namespace excite::host::cli
