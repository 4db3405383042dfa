// Internal: a tokenizer for Doom 3 text formats (.map, .mtr) on the shared
// core (text_cursor.h), reading numbers bit-exactly like the original's lexer.
//
// Tokens: quoted strings (no escapes, no newlines inside), names (letters,
// digits, '_', path characters '/', '\\', ':', '.'), numbers (digits with an
// optional fraction and exponent; a leading '-' is a separate punctuation
// token) and single-character punctuation. Comments (// and /* */) and
// whitespace are skipped.
//
// A malformed token (unterminated string or comment, bad number, a number
// that is not a finite float such as 1e999, control character) throws a
// SyntaxError after consuming it, so that a reader that catches it and
// carries on (the .mtr reader) makes progress. A leading UTF-8 byte-order
// mark is skipped (text_cursor.h).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "text/text_cursor.h"

namespace cmkit::detail {

/// What kind of token.
enum class TokenKind { End, String, Name, Number, Punct };

/// One token. `text` views the lexer's input (for strings: without quotes).
struct Token {
  TokenKind kind = TokenKind::End;
  std::string_view text;
  int line = 0;    ///< 1-based line of the first character
  int column = 0;  ///< 1-based column of the first character

  bool is(TokenKind k, std::string_view t) const { return kind == k && text == t; }
  bool isPunct(char c) const { return kind == TokenKind::Punct && text.size() == 1 && text[0] == c; }
};

/// Splits text into tokens on demand, with one token of look-ahead.
class Lexer : private TextCursor {
 public:
  /// The text must outlive the lexer.
  explicit Lexer(std::string_view text) : TextCursor(text), lines_(TextCursor::text()) {}

  /// The next token (kind End at the end of the input).
  Token next();
  /// The next token without consuming it.
  Token peek();

  /// A syntax error at a token's position.
  static SyntaxError errorAt(const Token& t, std::string message) {
    return SyntaxError{t.line, t.column, std::move(message)};
  }
  /// Throws errorAt(t, message).
  [[noreturn]] static void fail(const Token& t, std::string message) { throw errorAt(t, std::move(message)); }

 private:
  Token scan();

  LineCounter lines_;
  std::optional<Token> peeked_;
};

}  // namespace cmkit::detail
