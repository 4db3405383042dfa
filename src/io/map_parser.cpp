// The .map parser (the original's idMapFile, rewritten from the Doom 3
// .map format as the original reads it; include/cmkit/map.h says what is kept).
//
// Internally the lexer and the recursive-descent functions throw a
// SyntaxError that parseMapText catches and turns into an Error: nothing
// escapes the public API, and a failing parse never returns a partial map.
#include <cmath>
#include <new>
#include <utility>

#include "cmkit/map.h"
#include "cmkit/text_file.h"
#include "cmkit/tolerances.h"
#include "io/fields.h"
#include "io/map_crc.h"
#include "text/lexer.h"

namespace cmkit {

namespace {

using detail::Lexer;
using detail::Token;
using detail::TokenKind;

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    auto lower = [](char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

std::string describe(const Token& t) {
  switch (t.kind) {
    case TokenKind::End:
      return "the end of the file";
    case TokenKind::String:
      return "the string \"" + std::string(t.text) + "\"";
    case TokenKind::Number:
      return "the number " + std::string(t.text);
    case TokenKind::Name:
    case TokenKind::Punct:
      break;
  }
  return "'" + std::string(t.text) + "'";
}

/// Largest map version number accepted (Doom 3 writes 2, Quake 4 3).
constexpr float kMaxMapVersion = 1000000;

/// The parser state for one file.
class Parser {
 public:
  explicit Parser(std::string_view text) : lex_(text) {}

  MapFile parseFile(std::string fileName) {
    MapFile map;
    map.fileName = std::move(fileName);
    Token t = peek();
    if (t.is(TokenKind::Name, "Version")) {
      next();
      const Token v = peek();
      versionValue_ = number("the map version after 'Version'");
      // Doom 3 writes 2; anything beyond an int (found by fuzzing) is not a version.
      if (!(std::fabs(versionValue_) <= kMaxMapVersion))
        fail(v, "the map version is out of range: " + describe(v));
    }
    map.version = static_cast<int>(versionValue_);
    for (;;) {
      t = next();
      if (t.kind == TokenKind::End) break;
      if (!t.isPunct('{')) fail(t, "expected '{' to start an entity, found " + describe(t));
      map.entities.push_back(parseEntity(t, map.entities.empty()));
    }
    map.geometryCrc = detail::geometryCrc(map);
    return map;
  }

 private:
  [[noreturn]] static void fail(const Token& t, std::string message) { Lexer::fail(t, std::move(message)); }
  Token next() { return lex_.next(); }
  Token peek() { return lex_.peek(); }
  Token expectPunct(char c, std::string_view where) {
    Token t = next();
    if (!t.isPunct(c)) {
      fail(t, "expected '" + std::string(1, c) + "' " + std::string(where) + ", found " + describe(t));
    }
    return t;
  }
  /// A number, with an optional leading '-' token (so "-0" is -0.0f).
  float number(std::string_view what) {
    Token t = next();
    bool negate = false;
    if (t.isPunct('-')) {
      negate = true;
      t = next();
    }
    if (t.kind != TokenKind::Number) fail(t, "expected " + std::string(what) + ", found " + describe(t));
    const float v = *detail::originalNumberValue(t.text);  // validated by the lexer
    return negate ? -v : v;
  }
  void vector(float* out, int n, std::string_view what) {
    expectPunct('(', "to start " + std::string(what));
    for (int i = 0; i < n; ++i) out[i] = number("a number in " + std::string(what));
    expectPunct(')', "to end " + std::string(what) + " (" + std::to_string(n) + " numbers)");
  }
  /// The texture matrix ( ( a b c ) ( d e f ) ): read and dropped.
  void textureMatrix() {
    float m[3];
    expectPunct('(', "to start the texture matrix");
    vector(m, 3, "a texture matrix row");
    vector(m, 3, "a texture matrix row");
    expectPunct(')', "to end the texture matrix");
  }
  /// A Valve 220 texture axis [ x y z offset ]: read and dropped.
  void textureAxis(std::string_view what) {
    expectPunct('[', "to start " + std::string(what));
    for (int i = 0; i < 4; ++i) number("a number in " + std::string(what));
    expectPunct(']', "to end " + std::string(what) + " (4 numbers)");
  }
  std::string material(std::string_view where) {
    Token t = next();
    if (t.kind != TokenKind::String && t.kind != TokenKind::Name) {
      fail(t, "expected a material name " + std::string(where) + ", found " + describe(t));
    }
    std::string name(t.text);
    // Old maps (Version < 2) named materials without their folder.
    if (versionValue_ < 2.0f) name = "textures/" + name;
    return name;
  }
  /// Up to `n` optional numbers (the old per-side flags, absent in Version 3).
  void optionalNumbers(int n) {
    for (int i = 0; i < n; ++i) {
      const Token t = peek();
      if (t.kind == TokenKind::Number) {
        next();
      } else if (t.isPunct('-')) {
        number("a number");
      } else {
        return;
      }
    }
  }

  MapEntity parseEntity(const Token& open, bool world) {
    MapEntity entity;
    entity.line = open.line;
    for (;;) {
      Token t = next();
      if (t.isPunct('}')) return entity;
      if (t.isPunct('{')) {
        // Primitives are in the entity's local frame; the world's origin is
        // ignored. The origin known so far applies (editors write keys first).
        const Vec3 origin = world ? Vec3{} : entity.origin();
        entity.primitives.push_back(parsePrimitive(t, origin));
        continue;
      }
      if (t.kind == TokenKind::End) {
        fail(t, "the file ends inside the entity that starts on line " + std::to_string(open.line) +
                    " (expected '}')");
      }
      if (t.kind != TokenKind::String) {
        fail(t, "expected a quoted key, '{' (a primitive) or '}' (end of entity), found " + describe(t));
      }
      const Token v = next();
      if (v.kind != TokenKind::String) {
        fail(v, "expected the quoted value of key \"" + std::string(t.text) + "\", found " + describe(v));
      }
      checkPlacementKey(t, v);
      setKey(entity, t.text, v.text);
    }
  }
  /// The keys that place the entity's model ("origin", "rotation", "angle")
  /// must hold finite numbers: "inf", "nan" or "1e999" would put every
  /// vertex at infinity.
  static void checkPlacementKey(const Token& key, const Token& value) {
    std::size_t count = 0;
    if (equalsIgnoreCase(key.text, "origin")) count = 3;
    if (equalsIgnoreCase(key.text, "rotation")) count = 9;
    if (equalsIgnoreCase(key.text, "angle")) count = 1;
    if (count > 0 && !detail::scannedRealsFinite(value.text, count)) {
      fail(value, "the value of key \"" + std::string(key.text) +
                      "\" has a number that is not a finite float: \"" + std::string(value.text) + "\"");
    }
  }
  /// As the original's dictionary: a repeated key (case-insensitive)
  /// replaces the earlier value.
  static void setKey(MapEntity& entity, std::string_view key, std::string_view value) {
    for (auto& kv : entity.keyValues) {
      if (equalsIgnoreCase(kv.first, key)) {
        kv.second = value;
        return;
      }
    }
    entity.keyValues.emplace_back(std::string(key), std::string(value));
  }

  MapPrimitive parsePrimitive(const Token& open, const Vec3& origin) {
    const Token t = peek();
    if (t.is(TokenKind::Name, "brushDef3")) {
      next();
      return parseBrush(open, origin, BrushKind::PlaneEquations);
    }
    if (t.is(TokenKind::Name, "brushDef")) {
      next();
      return parseBrush(open, origin, BrushKind::ThreePoints);
    }
    if (t.is(TokenKind::Name, "patchDef2") || t.is(TokenKind::Name, "patchDef3")) {
      next();
      return parsePatch(open, origin, t.text == "patchDef3");
    }
    if (t.isPunct('(')) return parseBrush(open, origin, BrushKind::Quake3);
    fail(t,
         "unknown primitive " + describe(t) + ": expected brushDef3, patchDef2, patchDef3, brushDef or '('");
  }

  enum class BrushKind { PlaneEquations, ThreePoints, Quake3 };

  MapBrush parseBrush(const Token& open, const Vec3& origin, BrushKind kind) {
    MapBrush brush;
    brush.line = open.line;
    if (kind != BrushKind::Quake3) expectPunct('{', "after the brush keyword");
    for (;;) {
      const Token t = peek();
      if (t.isPunct('}')) {
        next();
        break;
      }
      if (!t.isPunct('(')) fail(t, "expected '(' (a brush side) or '}' (end of brush), found " + describe(t));
      brush.sides.push_back(parseSide(origin, kind));
    }
    if (kind != BrushKind::Quake3) expectPunct('}', "to end the primitive");
    return brush;
  }

  MapBrushSide parseSide(const Vec3& origin, BrushKind kind) {
    MapBrushSide side;
    const Token first = peek();
    if (kind == BrushKind::PlaneEquations) {
      float eq[4];
      vector(eq, 4, "a plane equation");
      side.plane = Plane(Vec3{eq[0], eq[1], eq[2]}, -eq[3]);
      textureMatrix();
      side.material = material("after the texture matrix");
      optionalNumbers(3);
      return side;
    }
    Vec3 points[3];
    for (Vec3& p : points) {
      float v[3];
      vector(v, 3, "a plane point");
      p = Vec3{v[0], v[1], v[2]} - origin;
    }
    // The plane through the three points: normal (p1-p2)x(p3-p2) normalised,
    // made exactly axial where it nearly is, then dist through p2.
    Vec3 n = (points[0] - points[1]).cross(points[2] - points[1]);
    if (n.normalize() == 0) fail(first, "the three points of this brush side are collinear: no plane");
    Plane plane(n, 0);
    plane.fixDegeneracies(0);
    plane.fitThroughPoint(points[1]);
    side.plane = plane;
    if (kind == BrushKind::ThreePoints) {
      textureMatrix();
      side.material = material("after the texture matrix");
      optionalNumbers(3);
      return side;
    }
    side.material = material("after the three plane points");
    if (peek().isPunct('[')) {
      // Valve 220 (TrenchBroom's "Doom 3 (Valve)" format): the texture axes
      // [ ux uy uz offset ] [ vx vy vz offset ], rotation, scale x, scale y,
      // then up to three optional flags. Only the plane matters here.
      textureAxis("the first Valve 220 texture axis [ x y z offset ]");
      textureAxis("the second Valve 220 texture axis [ x y z offset ]");
      for (int i = 0; i < 3; ++i) number("a Valve 220 texture rotation or scale");
      optionalNumbers(3);
      return side;
    }
    // Quake 3: shift x, shift y, rotation, scale x, scale y, then up to three
    // optional flags.
    for (int i = 0; i < 5; ++i) number("a Quake 3 texture shift, rotation or scale");
    optionalNumbers(3);
    return side;
  }

  int patchDimension(const Token& at, float v, std::string_view what, int limit) {
    if (!(v >= 0 && v <= static_cast<float>(limit)) || v != static_cast<float>(static_cast<int>(v))) {
      fail(at, "patch " + std::string(what) + " must be a whole number from 0 to " + std::to_string(limit));
    }
    return static_cast<int>(v);
  }

  MapPatch parsePatch(const Token& open, const Vec3& origin, bool explicitSubdivisions) {
    MapPatch patch;
    patch.line = open.line;
    patch.explicitSubdivisions = explicitSubdivisions;
    expectPunct('{', "after the patch keyword");
    patch.material = material("at the start of the patch");
    const Token header = peek();
    float info[7] = {};
    const int infoCount = explicitSubdivisions ? 7 : 5;
    vector(info, infoCount, explicitSubdivisions ? "the patchDef3 header" : "the patchDef2 header");
    patch.width = patchDimension(header, info[0], "width", tol::kMaxPatchControlSize);
    patch.height = patchDimension(header, info[1], "height", tol::kMaxPatchControlSize);
    if (patch.width < 3 || patch.height < 3 || patch.width % 2 == 0 || patch.height % 2 == 0) {
      fail(header, "patch of " + std::to_string(patch.width) + " x " + std::to_string(patch.height) +
                       " control points: width and height must be odd and at least 3");
    }
    if (explicitSubdivisions) {
      patch.horzSubdivisions =
          patchDimension(header, info[2], "horizontal subdivisions", tol::kMaxPatchGridSize);
      patch.vertSubdivisions =
          patchDimension(header, info[3], "vertical subdivisions", tol::kMaxPatchGridSize);
      if (patch.horzSubdivisions < 1 || patch.vertSubdivisions < 1) {
        fail(header, "patchDef3 subdivisions must be at least 1");
      }
      const long long outWidth = static_cast<long long>((patch.width - 1) / 2) * patch.horzSubdivisions + 1;
      const long long outHeight = static_cast<long long>((patch.height - 1) / 2) * patch.vertSubdivisions + 1;
      if (outWidth * outHeight > tol::kMaxPatchGridPoints) {
        fail(header, "patchDef3 subdivisions give " + std::to_string(outWidth) + " x " +
                         std::to_string(outHeight) + " points, more than cmkit's limit of " +
                         std::to_string(tol::kMaxPatchGridPoints));
      }
    }
    patch.points.resize(static_cast<std::size_t>(patch.width) * static_cast<std::size_t>(patch.height));
    expectPunct('(', "to start the patch control points");
    for (int j = 0; j < patch.width; ++j) {
      expectPunct('(', "to start a column of " + std::to_string(patch.height) + " patch control points");
      for (int i = 0; i < patch.height; ++i) {
        float v[5];
        vector(v, 5, "a patch control point ( x y z u v )");
        patch.points[static_cast<std::size_t>(i * patch.width + j)] = Vec3{v[0], v[1], v[2]} - origin;
      }
      expectPunct(')', "to end a column of " + std::to_string(patch.height) + " patch control points");
    }
    expectPunct(')', "to end the patch control points (" + std::to_string(patch.width) + " columns)");
    expectPunct('}', "to end the patch");
    expectPunct('}', "to end the primitive");
    return patch;
  }

  Lexer lex_;
  float versionValue_ = 1.0f;  // no "Version" line: an old (Quake 3 style) map
};

}  // namespace

std::optional<std::string_view> MapEntity::value(std::string_view key) const {
  for (const auto& kv : keyValues) {
    if (equalsIgnoreCase(kv.first, key)) return std::string_view(kv.second);
  }
  return std::nullopt;
}

Vec3 MapEntity::origin() const {
  float v[3] = {0, 0, 0};  // missing components stay 0
  if (const auto text = value("origin")) detail::scanReals(*text, v);
  return {v[0], v[1], v[2]};
}

Mat3 MapEntity::axis() const {
  if (const auto text = value("rotation")) {
    float m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // missing entries stay the identity's
    detail::scanReals(*text, m);
    return {{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}};
  }
  float yaw = 0;
  if (const auto text = value("angle")) detail::scanReals(*text, {&yaw, 1});
  return yaw == 0 ? Mat3::identity() : Mat3::fromAngles(0, yaw, 0);
}

Result<std::size_t> MapFile::findEntity(std::string_view nameOrIndex) const {
  if (nameOrIndex.starts_with('#')) {
    const std::optional<long long> n = detail::parseInt(nameOrIndex.substr(1));
    if (!n || *n < 0)
      return Error("bad entity number \"" + std::string(nameOrIndex) + "\" (expected #N, N >= 0)", fileName);
    if (std::size_t(*n) >= entities.size())
      return Error("no entity " + std::string(nameOrIndex) + ": the map has " +
                       std::to_string(entities.size()) + " entities, numbered from #0",
                   fileName);
    return std::size_t(*n);
  }
  for (std::size_t i = 0; i < entities.size(); ++i) {
    const auto name = entities[i].value("name");
    if (name && *name == nameOrIndex) return i;
  }
  return Error(
      "no entity named \"" + std::string(nameOrIndex) + "\" (use a \"name\" value, or #N for entity N)",
      fileName);
}

Result<MapFile> parseMapText(std::string_view text, std::string fileName) {
  try {
    Parser parser(text);
    return parser.parseFile(fileName);
  } catch (const detail::SyntaxError& e) {
    return detail::toError(e, std::move(fileName));
  } catch (const std::bad_alloc&) {
    return Error("out of memory while parsing the map", std::move(fileName));
  }
}

Result<MapFile> loadMapFile(const std::string& path) {
  Result<std::string> text = readTextFile(path);
  if (!text) return text.error();
  return parseMapText(*text, path);
}

}  // namespace cmkit
