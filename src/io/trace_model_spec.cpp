// Parsing the query format's trace model syntax ("box:-16,-16,0,16,16,72").
#include <optional>
#include <string>
#include <vector>

#include "cmkit/trace_model.h"
#include "io/fields.h"

namespace cmkit {
namespace {

// Splits on a separator (empty fields kept).
std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> parts;
  size_t pos = 0;
  while (true) {
    const size_t next = s.find(sep, pos);
    parts.push_back(s.substr(pos, next == std::string_view::npos ? std::string_view::npos : next - pos));
    if (next == std::string_view::npos) break;
    pos = next + 1;
  }
  return parts;
}

Result<std::vector<Real>> parseNumbers(std::string_view text, size_t count, std::string_view what) {
  std::vector<Real> values;
  std::string_view bad;
  if (!detail::parseRealList(text, values, &bad)) {
    return Error{"bad number '" + std::string(bad) + "' in " + std::string(what) +
                 " (numbers must be finite decimals)"};
  }
  if (count && values.size() != count) {
    return Error{std::string(what) + " needs " + std::to_string(count) + " numbers, got " +
                 std::to_string(values.size())};
  }
  return values;
}

Result<Bounds> parseBounds(std::string_view text, std::string_view what) {
  auto v = parseNumbers(text, 6, what);
  if (!v) return v.error();
  const auto& n = *v;
  return Bounds{{n[0], n[1], n[2]}, {n[3], n[4], n[5]}};
}

Result<std::vector<Vec3>> parsePoints(std::string_view text, std::string_view what) {
  std::vector<Vec3> pts;
  for (std::string_view part : split(text, ';')) {
    auto v = parseNumbers(part, 3, what);
    if (!v) return v.error();
    pts.push_back({(*v)[0], (*v)[1], (*v)[2]});
  }
  return pts;
}

Result<int> parseSides(std::string_view text, std::string_view what) {
  int n = 0;
  for (char c : text) {
    if (c < '0' || c > '9' || n > 1000)
      return Error{"bad side count '" + std::string(text) + "' in " + std::string(what)};
    n = n * 10 + (c - '0');
  }
  if (text.empty()) return Error{"missing side count in " + std::string(what)};
  return n;
}

}  // namespace

Result<TraceModel> TraceModel::parse(std::string_view spec) {
  const size_t colon = spec.find(':');
  const std::string_view kind = spec.substr(0, colon);
  const std::string_view rest = colon == std::string_view::npos ? std::string_view() : spec.substr(colon + 1);
  if (kind == "point") {
    if (colon != std::string_view::npos) return Error{"'point' takes no parameters"};
    return point();
  }
  if (colon == std::string_view::npos) {
    return Error{"unknown trace model '" + std::string(spec) +
                 "' (expected point, box:, octahedron:, dodecahedron:, cylinder:, cone:, bone:, "
                 "polygon:, polygonvolume: or hull:)"};
  }
  if (kind == "box" || kind == "octahedron" || kind == "dodecahedron") {
    auto b = parseBounds(rest, kind);
    if (!b) return b.error();
    if (kind == "box") return box(*b);
    if (b->min == b->max) return box(*b);  // zero size on all axes: a point
    return kind == "octahedron" ? octahedron(*b) : dodecahedron(*b);
  }
  if (kind == "cylinder" || kind == "cone") {
    const size_t c2 = rest.find(':');
    if (c2 == std::string_view::npos) return Error{std::string(kind) + " needs N:x0,y0,z0,x1,y1,z1"};
    auto sides = parseSides(rest.substr(0, c2), kind);
    if (!sides) return sides.error();
    auto b = parseBounds(rest.substr(c2 + 1), kind);
    if (!b) return b.error();
    if (b->min == b->max && *sides >= 3) return box(*b);
    return kind == "cylinder" ? cylinder(*b, *sides) : cone(*b, *sides);
  }
  if (kind == "bone") {
    auto v = parseNumbers(rest, 2, kind);
    if (!v) return v.error();
    return bone((*v)[0], (*v)[1]);
  }
  if (kind == "polygon") {
    auto pts = parsePoints(rest, kind);
    if (!pts) return pts.error();
    return polygon(*pts);
  }
  if (kind == "polygonvolume") {
    const size_t c2 = rest.find(':');
    if (c2 == std::string_view::npos) return Error{"polygonvolume needs T:x,y,z;x,y,z;..."};
    const std::optional<Real> thickness = detail::parseReal(rest.substr(0, c2));
    if (!thickness) return Error{"bad thickness in polygonvolume"};
    auto pts = parsePoints(rest.substr(c2 + 1), kind);
    if (!pts) return pts.error();
    return polygonVolume(*pts, *thickness);
  }
  if (kind == "hull") {
    auto pts = parsePoints(rest, kind);
    if (!pts) return pts.error();
    return convexHull(*pts);
  }
  return Error{"unknown trace model kind '" + std::string(kind) +
               "' (expected point, box, octahedron, dodecahedron, cylinder, cone, bone, polygon, "
               "polygonvolume or hull)"};
}

}  // namespace cmkit
