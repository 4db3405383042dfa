// Tokenizer for Doom 3 text formats; see lexer.h.
#include "text/lexer.h"

#include <cmath>
#include <utility>

namespace cmkit::detail {

namespace {

bool isAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool isHighByte(char c) { return static_cast<unsigned char>(c) >= 0x80; }
bool isNameStart(char c) {
  return isAlpha(c) || c == '_' || c == '/' || c == '\\' || c == ':' || isHighByte(c);
}
bool isNameChar(char c) { return isNameStart(c) || TextCursor::isDigit(c) || c == '.'; }

}  // namespace

Token Lexer::scan() {
  skipSpace();
  Token t;
  lines_.at(pos_, t.line, t.column);
  if (pos_ >= text_.size()) {
    t.kind = TokenKind::End;
    return t;
  }
  const std::size_t start = pos_;
  const char c = text_[pos_];
  if (c == '"') {
    const std::size_t end = quotedEnd(start + 1);
    if (end >= text_.size()) {
      pos_ = end;
      fail(t, "unterminated string: the file ends before the closing quote");
    }
    if (text_[end] != '"') {
      pos_ = end;
      fail(t, "unterminated string: a line break before the closing quote");
    }
    t.kind = TokenKind::String;
    t.text = text_.substr(start + 1, end - start - 1);
    pos_ = end + 1;
    return t;
  }
  if (isDigit(c) || (c == '.' && pos_ + 1 < text_.size() && isDigit(text_[pos_ + 1]))) {
    // The maximal run of word characters, with a sign allowed right after an
    // exponent letter; validated afterwards so that "12abc" is one bad token.
    ++pos_;
    while (pos_ < text_.size()) {
      const char d = text_[pos_];
      const char prev = text_[pos_ - 1];
      const bool sign = (d == '-' || d == '+') && (prev == 'e' || prev == 'E');
      if (!(isNameChar(d) || sign)) break;
      ++pos_;
    }
    t.kind = TokenKind::Number;
    t.text = text_.substr(start, pos_ - start);
    const std::optional<float> value = originalNumberValue(t.text);
    if (!value) fail(t, "bad number '" + std::string(t.text) + "'");
    if (!std::isfinite(*value))
      fail(t, "the number " + std::string(t.text) + " is not a finite float (beyond 3.4e38)");
    return t;
  }
  if (isNameStart(c)) {
    while (pos_ < text_.size() && isNameChar(text_[pos_])) ++pos_;
    t.kind = TokenKind::Name;
    t.text = text_.substr(start, pos_ - start);
    return t;
  }
  ++pos_;
  const auto uc = static_cast<unsigned char>(c);
  if (uc < 0x20 || uc == 0x7F)
    fail(t, "unexpected control character (byte " + std::to_string(static_cast<int>(uc)) + ")");
  t.kind = TokenKind::Punct;
  t.text = text_.substr(start, 1);
  return t;
}

Token Lexer::next() {
  if (peeked_) {
    Token t = *peeked_;
    peeked_.reset();
    return t;
  }
  return scan();
}

Token Lexer::peek() {
  if (!peeked_) peeked_ = scan();
  return *peeked_;
}

}  // namespace cmkit::detail
