#include "option_checks.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

namespace cmkit::cli {

namespace {

/// The number of all of `text` (strtod), if it is one and finite.
std::optional<double> finiteValue(const std::string& text) {
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size() || !std::isfinite(v) || !std::isfinite(float(v))) return std::nullopt;
  return v;
}

}  // namespace

CLI::Validator finiteNumber() { return finiteAtLeast(-std::numeric_limits<double>::infinity()); }

CLI::Validator finiteAtLeast(double lo) {
  const std::string name = std::isfinite(lo) ? fmt::format("FINITE >= {:g}", lo) : "FINITE";
  return CLI::Validator(
      [lo](std::string& text) -> std::string {
        const std::optional<double> v = finiteValue(text);
        if (!v) return "'" + text + "' is not a finite number";
        if (*v < lo) return fmt::format("'{}' is below {:g}", text, lo);
        return {};
      },
      name);
}

std::optional<Vec3> parseFiniteVec3(std::string_view text) {
  Real v[3] = {0, 0, 0};
  std::size_t pos = 0;
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',', pos);
    if ((i < 2) != (comma != std::string_view::npos)) return std::nullopt;
    const std::size_t end = i < 2 ? comma : text.size();
    const std::optional<double> value = finiteValue(std::string(text.substr(pos, end - pos)));
    if (!value) return std::nullopt;
    v[i] = Real(*value);
    pos = end + 1;
  }
  return Vec3{v[0], v[1], v[2]};
}

CLI::Validator finiteVec3() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (!parseFiniteVec3(text)) return "expected x,y,z (three finite numbers), got '" + text + "'";
        return {};
      },
      "X,Y,Z");
}

std::optional<Vec3> parseFiniteVec2or3(std::string_view text) {
  if (std::count(text.begin(), text.end(), ',') == 1) {
    const std::optional<Vec3> v = parseFiniteVec3(std::string(text) + ",0");
    return v;
  }
  return parseFiniteVec3(text);
}

CLI::Validator finiteVec2or3() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (!parseFiniteVec2or3(text)) return "expected x,y or x,y,z (finite numbers), got '" + text + "'";
        return {};
      },
      "X,Y[,Z]");
}

}  // namespace cmkit::cli
