// The .cm cursor: see cm_cursor.h.
#include "text/cm_cursor.h"

#include <cmath>
#include <utility>

namespace cmkit::detail {

namespace {

bool isNameChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || TextCursor::isDigit(c) || c == '_';
}
bool isBlank(char c) { return c == ' ' || c == '\t'; }

}  // namespace

void CmCursor::fail(std::string message) {
  skipSpace();
  failAt(pos_, std::move(message));
}

std::string CmCursor::describeNext() {
  skipSpace();
  if (pos_ >= text_.size()) return "the end of the file";
  const char c = text_[pos_];
  const auto uc = static_cast<unsigned char>(c);
  if (uc < 0x20 || uc >= 0x7F) return "byte " + std::to_string(int(uc));
  std::size_t end = pos_ + 1;
  if (isNameChar(c)) {
    while (end < text_.size() && end - pos_ < 40 && (isNameChar(text_[end]) || text_[end] == '.')) ++end;
  } else if (c == '"') {
    while (end < text_.size() && end - pos_ < 40 && text_[end] != '"' && text_[end] != '\n') ++end;
    if (end < text_.size() && text_[end] == '"') ++end;
  }
  return "'" + std::string(text_.substr(pos_, end - pos_)) + "'";
}

bool CmCursor::more() {
  skipSpace();
  return pos_ < text_.size();
}

std::size_t CmCursor::tokenOffset() {
  skipSpace();
  return pos_;
}

bool CmCursor::acceptPunct(char c) {
  skipSpace();
  if (pos_ < text_.size() && text_[pos_] == c) {
    ++pos_;
    return true;
  }
  return false;
}

void CmCursor::expectPunct(char c, std::string_view context) {
  if (acceptPunct(c)) return;
  fail("expected '" + std::string(1, c) + "' " + std::string(context) + ", found " + describeNext());
}

bool CmCursor::atUnsignedNumber() {
  skipSpace();
  return pos_ < text_.size() && isDigit(text_[pos_]);
}

std::string_view CmCursor::readName() {
  skipSpace();
  const std::size_t start = pos_;
  while (pos_ < text_.size() && isNameChar(text_[pos_])) ++pos_;
  return text_.substr(start, pos_ - start);
}

std::string_view CmCursor::expectString(std::string_view what) {
  skipSpace();
  if (pos_ >= text_.size() || text_[pos_] != '"')
    fail("expected " + std::string(what) + ", found " + describeNext());
  const std::size_t start = pos_ + 1;
  const std::size_t end = quotedEnd(start);
  if (end >= text_.size() || text_[end] != '"')
    failAt(pos_, "unterminated string (" + std::string(what) + ")");
  pos_ = end + 1;
  return text_.substr(start, end - start);
}

std::string_view CmCursor::expectWord(std::string_view what) {
  skipSpace();
  if (pos_ < text_.size() && text_[pos_] == '"') return expectString(what);
  const std::size_t start = pos_;
  while (pos_ < text_.size() && (isNameChar(text_[pos_]) || text_[pos_] == '.')) ++pos_;
  if (pos_ == start) fail("expected " + std::string(what) + ", found " + describeNext());
  return text_.substr(start, pos_ - start);
}

bool CmCursor::readMinus() {
  if (pos_ >= text_.size() || text_[pos_] != '-') return false;
  ++pos_;
  while (pos_ < text_.size() && isBlank(text_[pos_])) ++pos_;  // "- 5" is -5 to the original
  return true;
}

std::int64_t CmCursor::expectInt(std::string_view what, std::int64_t lo, std::int64_t hi) {
  skipSpace();
  const std::size_t start = pos_;
  const bool negative = readMinus();
  const std::size_t digits = pos_;
  std::int64_t value = 0;
  bool overflow = false;
  while (pos_ < text_.size() && isDigit(text_[pos_])) {
    if (value > (std::int64_t(1) << 40)) overflow = true;
    if (!overflow) value = value * 10 + (text_[pos_] - '0');
    ++pos_;
  }
  if (pos_ == digits) {
    pos_ = start;
    fail("expected " + std::string(what) + " (an integer), found " + describeNext());
  }
  if (pos_ < text_.size() && (text_[pos_] == '.' || text_[pos_] == 'e' || text_[pos_] == 'E')) {
    failAt(start, "expected " + std::string(what) + " (an integer), found a fraction or exponent");
  }
  if (negative) value = -value;
  if (overflow || value < lo || value > hi) {
    failAt(start, std::string(what) + " " + std::string(text_.substr(start, pos_ - start)) +
                      " out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return value;
}

float CmCursor::expectFloat(std::string_view what) {
  skipSpace();
  const std::size_t start = pos_;
  const bool negative = readMinus();
  const std::size_t numStart = pos_;
  const std::size_t n = text_.size();
  while (pos_ < n && isDigit(text_[pos_])) ++pos_;
  if (pos_ < n && text_[pos_] == '.') {
    ++pos_;
    while (pos_ < n && isDigit(text_[pos_])) ++pos_;
  }
  if (pos_ < n && pos_ > numStart && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
    ++pos_;
    if (pos_ < n && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
    while (pos_ < n && isDigit(text_[pos_])) ++pos_;
  }
  const std::optional<float> v = originalNumberValue(text_.substr(numStart, pos_ - numStart));
  if (!v) {
    pos_ = start;
    fail("expected " + std::string(what) + " (a number), found " + describeNext());
  }
  if (!std::isfinite(*v)) {
    failAt(start, std::string(what) + " " + std::string(text_.substr(start, pos_ - start)) +
                      " is not a finite float");
  }
  return negative ? -*v : *v;
}

}  // namespace cmkit::detail
