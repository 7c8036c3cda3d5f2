// SPDX-License-Identifier: MIT
#pragma once
// Names and paths written into generated code (`excite export`: MATLAB/Octave, Python, the
// step table's comments) are data, never code: each is escaped for the language it lands
// in, or refused naming its field when the language has no escape for it. A model file's
// channel name or a file name must not be able to close a string or a comment and start a
// statement (issue 40 §1).

#include <string>
#include <string_view>

namespace excite::host {

/// Throws std::invalid_argument `FIELD = VALUE, expected UTF-8 text` when `value` is not
/// valid UTF-8 (a Python source file is UTF-8; JSON strings are too).
void require_utf8(const std::string& field, std::string_view value);

/// `value` for a one-line comment (MATLAB `%`, Python `#`, the step table's `#`): every
/// control byte (below 0x20, and 0x7f) written as `\xNN`, so no newline or carriage return
/// can end the comment; every other byte kept. For reading, not for reading back.
std::string comment_text(std::string_view value);

/// The body of a Python triple-quoted, non-raw string literal delimited by `quote` (' or "):
/// backslash and every `quote` escaped (so no three quotes in a row can close it), every
/// control byte but the newline as `\xNN` (the same code point), other bytes kept (UTF-8,
/// checked by the caller). Python reads the literal back as exactly `value`.
std::string python_triple_quoted_body(std::string_view value, char quote);

/// A MATLAB/Octave single-quoted char literal: `'` doubled. A control byte has no escape in
/// it (a newline ends the line, the statement and the string): throws std::invalid_argument
/// `FIELD = VALUE, expected a name without control characters ...`.
std::string matlab_string_literal(const std::string& field, std::string_view value);

/// `value` shown in a message: comment_text(), cut to 40 bytes with "…".
std::string shown_text(std::string_view value);

}  // namespace excite::host
