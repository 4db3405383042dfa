// Internal: a tokenizer for Doom 3 text formats (.map, .mtr), reading
// numbers bit-exactly like the original's lexer.
//
// Tokens: quoted strings (no escapes, no newlines inside), names (letters,
// digits, '_', path characters '/', '\\', ':', '.'), numbers (digits with an
// optional fraction and exponent; a leading '-' is a separate punctuation
// token) and single-character punctuation. Comments (// and /* */) and
// whitespace are skipped. Line breaks are LF, CRLF or a bare CR (each counts
// as one line), so files with any mix of endings report the same lines.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "cmkit/result.h"

namespace cmkit::text {

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

/// The value of a number token's text exactly as the original lexer computes
/// it: integer digits accumulated in double (v = v*10 + d), fraction digits
/// with a running multiplier (m = 0.1; v += d*m; m *= 0.1), the exponent as
/// 10^n built by repeated multiplication and applied by * or /, then a cast
/// to float. nullopt when the text is not a well-formed number.
std::optional<float> originalNumberValue(std::string_view text);

/// Splits text into tokens on demand, with one token of look-ahead.
class Lexer {
 public:
  /// `fileName` is used in errors. The text must outlive the lexer.
  Lexer(std::string_view text, std::string fileName);

  /// The next token (kind End at the end of the input), or an error for a
  /// malformed token (unterminated string or comment, bad number, control
  /// character).
  Result<Token> next();
  /// The next token without consuming it.
  Result<Token> peek();

  /// An error at a token's position.
  Error errorAt(const Token& t, std::string message) const;
  /// An error at the current position (after the last token read).
  Error errorHere(std::string message) const;
  const std::string& fileName() const { return fileName_; }

 private:
  Result<Token> scan();
  void skipWhitespaceAndComments(std::optional<Error>& error);
  void advance();  // one character, keeping line/column

  std::string_view text_;
  std::string fileName_;
  std::size_t pos_ = 0;
  int line_ = 1;
  int column_ = 1;
  std::optional<Token> peeked_;
};

}  // namespace cmkit::text
