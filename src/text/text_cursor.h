// Internal: the core that the text readers share (the token lexer of .map
// and .mtr in lexer.h, the .cm cursor in cm_cursor.h): the original's number
// conversion, whitespace and comment skipping, line/column counting and the
// one syntax error type.
//
// Errors: the readers throw SyntaxError (never across the public API); the
// public entry points catch it and return toError(e, fileName), an Error with
// file:line:column.
//
// Line breaks are LF, CRLF or a bare CR (each counts as one line), so files
// with any mix of endings report the same lines. Columns count bytes from 1;
// the CR of a CRLF is not counted.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "cmkit/result.h"

namespace cmkit::detail {

/// A syntax error at a 1-based line and column of the text being read.
struct SyntaxError {
  int line = 0;
  int column = 0;
  std::string message;
};

/// The Error a public entry point returns for a SyntaxError in `fileName`.
Error toError(const SyntaxError& e, std::string fileName);

/// The UTF-8 byte-order mark that some editors put at the start of a file.
inline constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

/// `text` without a leading UTF-8 byte-order mark. Every reader skips it, so
/// that line 1, column 1 is the first visible character.
inline std::string_view withoutUtf8Bom(std::string_view text) {
  return text.substr(0, kUtf8Bom.size()) == kUtf8Bom ? text.substr(kUtf8Bom.size()) : text;
}

/// The value of a number's text exactly as the original lexer computes it:
/// integer digits accumulated in double (v = v*10 + d), fraction digits with a
/// running multiplier (m = 0.1; v += d*m; m *= 0.1), the exponent as 10^n
/// built by repeated multiplication and applied by * or /, then a cast to
/// float. No sign. nullopt when the text is not a well-formed number; the
/// value may be infinite (1e999 overflows the float): the readers reject it.
std::optional<float> originalNumberValue(std::string_view text);

/// Line and column of byte offsets of one text. Counting goes forward from
/// the last offset asked for, so asking in increasing order reads the text
/// once; an earlier offset starts again from the beginning.
class LineCounter {
 public:
  explicit LineCounter(std::string_view text) : text_(text) {}
  void at(std::size_t offset, int& line, int& column);

 private:
  std::string_view text_;
  std::size_t offset_ = 0;
  int line_ = 1;
  int column_ = 1;
};

/// A position in a text (which outlives it) with whitespace and comment
/// skipping; the readers build their tokens on it. A leading UTF-8
/// byte-order mark is not part of the text (offsets, lines and columns count
/// from after it).
class TextCursor {
 public:
  explicit TextCursor(std::string_view text) : text_(withoutUtf8Bom(text)) {}

  std::string_view text() const { return text_; }
  /// Byte offset of the cursor.
  std::size_t offset() const { return pos_; }

  /// Skips whitespace, // comments and /* */ comments. An unterminated /*
  /// throws a SyntaxError at its start (the cursor is then at the end).
  void skipSpace() {
    const std::size_t n = text_.size();
    while (pos_ < n) {
      const char c = text_[pos_];
      if (isSpace(c)) {
        ++pos_;
      } else if (c == '/' && pos_ + 1 < n && (text_[pos_ + 1] == '/' || text_[pos_ + 1] == '*')) {
        skipComment();
      } else {
        return;
      }
    }
  }

  /// Throws a SyntaxError at a byte offset.
  [[noreturn]] void failAt(std::size_t offset, std::string message) const;

  static bool isDigit(char c) { return c >= '0' && c <= '9'; }
  static bool isSpace(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  static bool isLineBreak(char c) { return c == '\n' || c == '\r'; }

 protected:
  /// Where the body of a quoted string starting at `body` (just after the
  /// opening quote) stops: the closing quote, or a line break or the end of
  /// the text for an unterminated string (no escapes, no line breaks inside).
  std::size_t quotedEnd(std::size_t body) const {
    std::size_t end = body;
    while (end < text_.size() && text_[end] != '"' && !isLineBreak(text_[end])) ++end;
    return end;
  }

  std::string_view text_;
  std::size_t pos_ = 0;

 private:
  void skipComment();  // at "//" or "/*"
};

}  // namespace cmkit::detail
