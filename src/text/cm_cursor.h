// Internal: the fast path of the text core (text_cursor.h) for .cm text
// (the original reads it with idLexer).
//
// It reads the few token kinds the grammar needs directly from the buffer,
// without building token objects: punctuation, names, quoted strings,
// integers and floats (a leading '-' on the same line, as the original's
// ParseInt/ParseFloat accept). Whitespace and comments are skipped by the
// core. Line and column are not tracked while reading: they are counted
// from the byte offset only when an error is thrown (a SyntaxError, caught by
// the reader at its top level, never across the public API).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "text/text_cursor.h"

namespace cmkit::detail {

/// Reads .cm tokens from a text that outlives it.
class CmCursor : public TextCursor {
 public:
  explicit CmCursor(std::string_view text) : TextCursor(text) {}

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
  /// Throws a SyntaxError at the next token (failAt: at a byte offset).
  [[noreturn]] void fail(std::string message);

 private:
  /// Consumes a leading '-' and the blanks after it; true when there was one.
  bool readMinus();
  std::string describeNext();
};

}  // namespace cmkit::detail
