// The shared core of the text readers: see text_cursor.h.
#include "text/text_cursor.h"

#include <utility>

namespace cmkit::detail {

Error toError(const SyntaxError& e, std::string fileName) {
  return Error(e.message, std::move(fileName), e.line, e.column);
}

std::optional<float> originalNumberValue(std::string_view s) {
  using C = TextCursor;
  std::size_t i = 0;
  double value = 0.0;
  bool anyDigit = false;
  while (i < s.size() && C::isDigit(s[i])) {
    value = value * 10.0 + static_cast<double>(s[i] - '0');
    anyDigit = true;
    ++i;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    double m = 0.1;
    while (i < s.size() && C::isDigit(s[i])) {
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
    while (i < s.size() && C::isDigit(s[i])) {
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

void LineCounter::at(std::size_t offset, int& line, int& column) {
  if (offset > text_.size()) offset = text_.size();
  if (offset < offset_) {
    offset_ = 0;
    line_ = 1;
    column_ = 1;
  }
  for (; offset_ < offset; ++offset_) {
    const char c = text_[offset_];
    if (c == '\n' || (c == '\r' && (offset_ + 1 >= text_.size() || text_[offset_ + 1] != '\n'))) {
      ++line_;
      column_ = 1;
    } else if (c != '\r') {
      ++column_;
    }
  }
  line = line_;
  column = column_;
}

void TextCursor::failAt(std::size_t offset, std::string message) const {
  SyntaxError e;
  LineCounter(text_).at(offset, e.line, e.column);
  e.message = std::move(message);
  throw e;
}

void TextCursor::skipComment() {
  const std::size_t start = pos_;
  if (text_[pos_ + 1] == '/') {
    pos_ += 2;
    while (pos_ < text_.size() && !isLineBreak(text_[pos_])) ++pos_;
    return;
  }
  const std::size_t end = text_.find("*/", pos_ + 2);
  if (end == std::string_view::npos) {
    pos_ = text_.size();  // a reader that carries on after the error finds the end
    failAt(start, "unterminated /* comment (no closing */ before the end of the file)");
  }
  pos_ = end + 2;
}

}  // namespace cmkit::detail
