// The shared pieces of the query-line format: see fields.h.
#include "io/fields.h"

#include "text/text_cursor.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

namespace cmkit::detail {

namespace {

bool isLineSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }
bool isSeparator(char c) { return c == ' ' || c == '\t'; }

}  // namespace

std::string_view trimLine(std::string_view s) {
  s = withoutUtf8Bom(s);  // the first line of a file saved with a byte-order mark
  while (!s.empty() && isLineSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && isLineSpace(s.back())) s.remove_suffix(1);
  return s;
}

std::pair<std::string_view, std::string_view> splitWord(std::string_view line) {
  const std::size_t sp = line.find_first_of(" \t");
  if (sp == std::string_view::npos) return {line, {}};
  return {line.substr(0, sp), line.substr(sp)};
}

Fields::Fields(std::string_view text) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    while (pos < text.size() && isSeparator(text[pos])) ++pos;
    std::size_t end = pos;
    while (end < text.size() && !isSeparator(text[end])) ++end;
    const std::string_view token = text.substr(pos, end - pos);
    pos = end;
    if (token.empty()) continue;
    const std::size_t eq = token.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      if (stray_.empty()) stray_ = token;
      continue;
    }
    fields_.emplace_back(token.substr(0, eq), token.substr(eq + 1));
  }
}

std::optional<std::string_view> Fields::get(std::string_view key) const {
  for (auto it = fields_.rbegin(); it != fields_.rend(); ++it)
    if (it->first == key) return it->second;
  return std::nullopt;
}

std::optional<Real> parseReal(std::string_view text, Finite finite) {
  if (text.empty()) return std::nullopt;
  const std::string s(text);
  char* end = nullptr;
  const float v = std::strtof(s.c_str(), &end);
  if (end != s.c_str() + s.size()) return std::nullopt;
  if (finite == Finite::Required && !std::isfinite(v)) return std::nullopt;
  return v;
}

bool parseRealList(std::string_view text, std::vector<Real>& out, std::string_view* bad, Finite finite) {
  std::size_t pos = 0;
  for (;;) {
    const std::size_t comma = text.find(',', pos);
    const std::string_view part =
        text.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos);
    const std::optional<Real> v = parseReal(part, finite);
    if (!v) {
      if (bad) *bad = part;
      return false;
    }
    out.push_back(*v);
    if (comma == std::string_view::npos) return true;
    pos = comma + 1;
  }
}

std::optional<Vec3> parseVec3(std::string_view text, Finite finite) {
  std::vector<Real> v;
  if (!parseRealList(text, v, nullptr, finite) || v.size() != 3) return std::nullopt;
  return Vec3{v[0], v[1], v[2]};
}

std::optional<Mat3> parseMat3(std::string_view text, Finite finite) {
  std::vector<Real> v;
  if (!parseRealList(text, v, nullptr, finite) || v.size() != 9) return std::nullopt;
  return Mat3{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}, {v[6], v[7], v[8]}};
}

std::optional<long long> parseInt(std::string_view text) {
  if (text.empty()) return std::nullopt;
  const std::string s(text);
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

bool scannedRealsFinite(std::string_view text, std::size_t count) {
  const std::string s(text);
  const char* p = s.c_str();
  for (std::size_t i = 0; i < count; ++i) {
    char* end = nullptr;
    const float v = std::strtof(p, &end);
    if (end == p) return true;  // scanning stops here: what was read is finite
    if (!std::isfinite(v)) return false;
    p = end;
  }
  return true;
}

void scanReals(std::string_view text, std::span<float> out) {
  const char* p = text.data();
  const char* end = p + text.size();
  for (float& slot : out) {
    while (p < end && (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')) ++p;
    if (p < end && *p == '+') ++p;
    float v = 0;
    const auto r = std::from_chars(p, end, v);
    if (r.ec != std::errc()) break;
    slot = v;
    p = r.ptr;
  }
}

}  // namespace cmkit::detail
