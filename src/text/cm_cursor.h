// Internal: a fast cursor over .cm text (the original reads it with idLexer).
//
// It reads the few token kinds the grammar needs directly from the buffer,
// without building token objects: punctuation, names, quoted strings,
// integers and floats (a leading '-' on the same line, as the original's
// ParseInt/ParseFloat accept). Whitespace and C/C++ comments are skipped.
// Line and column are not tracked while reading; an error records the byte
// offset and lineColumn() computes them only when a message is made.
//
// Errors are thrown as CmSyntaxError and caught by the reader at its top
// level (never across the public API).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace cmkit::cmtext {

/// A syntax error at a byte offset of the text.
struct CmSyntaxError {
  std::size_t offset = 0;
  std::string message;
};

/// 1-based line and column of a byte offset (LF, CRLF and bare CR each end
/// one line).
void lineColumn(std::string_view text, std::size_t offset, int& line, int& column);

/// Reads .cm tokens from a text that outlives it.
class CmCursor {
 public:
  explicit CmCursor(std::string_view text) : text_(text) {}

  /// Skips whitespace and comments; true if anything but the end follows.
  bool more();
  /// Byte offset of the next token (after skipping whitespace and comments).
  std::size_t tokenOffset();
  /// True (and consumed) if the next token is the punctuation c.
  bool acceptPunct(char c);
  /// The next token must be the punctuation c.
  void expectPunct(char c, std::string_view context);
  /// True if the next character is a digit (an unsigned number follows).
  bool atUnsignedNumber();
  /// A name (letters, digits, '_'); empty if the next token is not one.
  std::string_view readName();
  /// A quoted string's contents (no escapes; no line break inside).
  std::string_view expectString(std::string_view what);
  /// A name or a quoted string (the original compares token text only).
  std::string_view expectWord(std::string_view what);
  /// An integer in [lo, hi], optionally with a leading '-'.
  std::int64_t expectInt(std::string_view what, std::int64_t lo, std::int64_t hi);
  /// A finite float converted exactly as the original lexer converts it,
  /// optionally with a leading '-' (giving -0 for "-0").
  float expectFloat(std::string_view what);
  /// Throws a CmSyntaxError at the next token.
  [[noreturn]] void fail(std::string message);
  /// Throws a CmSyntaxError at a given offset.
  [[noreturn]] static void failAt(std::size_t offset, std::string message);

 private:
  void skip();
  std::string describeNext();

  std::string_view text_;
  std::size_t pos_ = 0;
};

}  // namespace cmkit::cmtext
