// Tokenizer for Doom 3 text formats; see lexer.h.
#include "text/lexer.h"

#include <utility>

namespace cmkit::text {

namespace {

bool isDigit(char c) { return c >= '0' && c <= '9'; }
bool isAlpha(char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); }
bool isHighByte(char c) { return static_cast<unsigned char>(c) >= 0x80; }
bool isNameStart(char c) {
  return isAlpha(c) || c == '_' || c == '/' || c == '\\' || c == ':' || isHighByte(c);
}
bool isNameChar(char c) { return isNameStart(c) || isDigit(c) || c == '.'; }
bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

}  // namespace

std::optional<float> originalNumberValue(std::string_view s) {
  std::size_t i = 0;
  double value = 0.0;
  bool anyDigit = false;
  while (i < s.size() && isDigit(s[i])) {
    value = value * 10.0 + static_cast<double>(s[i] - '0');
    anyDigit = true;
    ++i;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    double m = 0.1;
    while (i < s.size() && isDigit(s[i])) {
      value = value + static_cast<double>(s[i] - '0') * m;
      m *= 0.1;
      anyDigit = true;
      ++i;
    }
  }
  if (!anyDigit) return std::nullopt;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    bool divide = false;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) {
      divide = s[i] == '-';
      ++i;
    }
    if (i >= s.size()) return std::nullopt;
    int power = 0;
    while (i < s.size() && isDigit(s[i])) {
      // Beyond a few hundred the double overflows to inf or underflows to 0
      // anyway; clamping keeps the loop short for hostile input.
      if (power < 1000) power = power * 10 + (s[i] - '0');
      ++i;
    }
    double scale = 1.0;
    for (int k = 0; k < power; ++k) scale *= 10.0;
    value = divide ? value / scale : value * scale;
  }
  if (i != s.size()) return std::nullopt;
  return static_cast<float>(value);
}

Lexer::Lexer(std::string_view text, std::string fileName) : text_(text), fileName_(std::move(fileName)) {}

void Lexer::advance() {
  const char c = text_[pos_++];
  if (c == '\n' || (c == '\r' && (pos_ >= text_.size() || text_[pos_] != '\n'))) {
    ++line_;
    column_ = 1;
  } else if (c != '\r') {
    ++column_;
  }
}

void Lexer::skipWhitespaceAndComments(std::optional<Error>& error) {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (isSpace(c)) {
      advance();
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
      while (pos_ < text_.size() && text_[pos_] != '\n' && text_[pos_] != '\r') advance();
    } else if (c == '/' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '*') {
      const int startLine = line_;
      const int startColumn = column_;
      advance();
      advance();
      bool closed = false;
      while (pos_ < text_.size()) {
        if (text_[pos_] == '*' && pos_ + 1 < text_.size() && text_[pos_ + 1] == '/') {
          advance();
          advance();
          closed = true;
          break;
        }
        advance();
      }
      if (!closed) {
        error = Error("unterminated /* comment (no closing */ before the end of the file)", fileName_,
                      startLine, startColumn);
        return;
      }
    } else {
      return;
    }
  }
}

Result<Token> Lexer::scan() {
  std::optional<Error> error;
  skipWhitespaceAndComments(error);
  if (error) return *error;
  Token t;
  t.line = line_;
  t.column = column_;
  if (pos_ >= text_.size()) {
    t.kind = TokenKind::End;
    return t;
  }
  const std::size_t start = pos_;
  const char c = text_[pos_];
  if (c == '"') {
    advance();
    const std::size_t body = pos_;
    while (pos_ < text_.size() && text_[pos_] != '"') {
      if (text_[pos_] == '\n' || text_[pos_] == '\r')
        return errorAt(t, "unterminated string: a line break before the closing quote");
      advance();
    }
    if (pos_ >= text_.size())
      return errorAt(t, "unterminated string: the file ends before the closing quote");
    t.kind = TokenKind::String;
    t.text = text_.substr(body, pos_ - body);
    advance();
    return t;
  }
  if (isDigit(c) || (c == '.' && pos_ + 1 < text_.size() && isDigit(text_[pos_ + 1]))) {
    // The maximal run of word characters, with a sign allowed right after an
    // exponent letter; validated afterwards so that "12abc" is one bad token.
    advance();
    while (pos_ < text_.size()) {
      const char d = text_[pos_];
      const char prev = text_[pos_ - 1];
      const bool sign = (d == '-' || d == '+') && (prev == 'e' || prev == 'E');
      if (!(isNameChar(d) || sign)) break;
      advance();
    }
    t.kind = TokenKind::Number;
    t.text = text_.substr(start, pos_ - start);
    if (!originalNumberValue(t.text)) return errorAt(t, "bad number '" + std::string(t.text) + "'");
    return t;
  }
  if (isNameStart(c)) {
    while (pos_ < text_.size() && isNameChar(text_[pos_])) advance();
    t.kind = TokenKind::Name;
    t.text = text_.substr(start, pos_ - start);
    return t;
  }
  const auto uc = static_cast<unsigned char>(c);
  if (uc < 0x20 || uc == 0x7F) {
    advance();  // so that a caller that carries on makes progress
    return errorAt(t, "unexpected control character (byte " + std::to_string(static_cast<int>(uc)) + ")");
  }
  advance();
  t.kind = TokenKind::Punct;
  t.text = text_.substr(start, 1);
  return t;
}

Result<Token> Lexer::next() {
  if (peeked_) {
    Token t = *peeked_;
    peeked_.reset();
    return t;
  }
  return scan();
}

Result<Token> Lexer::peek() {
  if (!peeked_) {
    auto t = scan();
    if (!t) return t;
    peeked_ = *t;
  }
  return *peeked_;
}

Error Lexer::errorAt(const Token& t, std::string message) const {
  return Error(std::move(message), fileName_, t.line, t.column);
}

Error Lexer::errorHere(std::string message) const {
  return Error(std::move(message), fileName_, line_, column_);
}

}  // namespace cmkit::text
