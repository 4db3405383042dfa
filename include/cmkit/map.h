// map.h: Doom 3 .map files, parsed (the original's idMapFile).
//
// Parsing keeps what collision models need: entities with their key/value
// pairs and their primitives (brushes and patches) in file order, and the
// geometry CRC that .cm files carry on their third line.
//
// Parser behaviour worth knowing:
// - Accepted: "Version 2" / "Version 3" (Quake 4 sides without the three
//   trailing integers; in fact up to three trailing numbers are optional in
//   any version), no Version line (an old map: version 1, material names get
//   "textures/" prefixed), // and /* */ comments, LF, CRLF and bare CR line
//   endings (line numbers count each once), primitives brushDef3, brushDef
//   (three points per side), patchDef2, patchDef3, keyword-less Quake 3
//   brushes and TrenchBroom's "Doom 3 (Valve)" brushes (three points, material,
//   Valve 220 texture axes [ x y z offset ] twice, rotation and scales; the
//   texture data is dropped, the plane comes from the points as for brushDef).
//   Numbers are read bit-exactly like the original lexer.
// - Brushes are kept whatever their number of sides (even fewer than 4, even
//   0): the parser reports what the file says; the model builder skips
//   brushes that do not enclose a volume, with a warning.
// - A key that repeats in an entity (case-insensitive) replaces the earlier
//   value, as the original's dictionary does.
// - Rejected with an Error (file:line:column, what was expected): malformed
//   tokens and structure, a brushDef side whose three points are collinear,
//   patches whose width or height is even or below 3 (the original reads past
//   its control points), patchDef3 subdivisions below 1, grids beyond the
//   limits in tolerances.h. A failed parse returns no map.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "cmkit/math.h"
#include "cmkit/result.h"

namespace cmkit {

/// One side of a brush: its plane and material.
struct MapBrushSide {
  /// The plane as read: the file's (a b c d) means a*x + b*y + c*z + d = 0,
  /// so normal = (a, b, c) and dist = -d. Old-style three-point brushDef
  /// sides get the plane through their points (shifted by -origin).
  Plane plane;
  /// The material name exactly as written in the file (not canonicalised).
  std::string material;
};

/// A convex brush: the intersection of the back half-spaces of its sides.
struct MapBrush {
  /// The sides in file order.
  std::vector<MapBrushSide> sides;
  int line = 0;  ///< line of the primitive in the file (for messages)
};

/// A Bézier patch mesh (patchDef2, or patchDef3 with explicit subdivisions).
struct MapPatch {
  std::string material;               ///< as written in the file
  int width = 0;                      ///< control points along the first index (odd, >= 3)
  int height = 0;                     ///< control points along the second index (odd, >= 3)
  bool explicitSubdivisions = false;  ///< patchDef3
  int horzSubdivisions = 0;           ///< patchDef3 only
  int vertSubdivisions = 0;           ///< patchDef3 only
  /// width*height control points, already minus the entity origin: the
  /// file's group j (0..width-1), point i (0..height-1) is at i*width + j.
  std::vector<Vec3> points;
  /// Line of the patch in the file (1-based).
  int line = 0;
};

using MapPrimitive = std::variant<MapBrush, MapPatch>;

/// An entity: key/value pairs and primitives in file order.
struct MapEntity {
  /// Key/value pairs in file order.
  std::vector<std::pair<std::string, std::string>> keyValues;
  /// Brushes and patches in file order.
  std::vector<MapPrimitive> primitives;
  /// Line of the entity in the file (1-based).
  int line = 0;

  /// The value of the first pair with this key (case-insensitive, as the
  /// original's dictionary), or nullopt.
  std::optional<std::string_view> value(std::string_view key) const;
  /// The "origin" key parsed as three numbers, or (0,0,0).
  Vec3 origin() const;
  /// The orientation the game gives the entity (and so its collision
  /// model): the "rotation" key (nine numbers, the rows of the axis), else a
  /// yaw of "angle" degrees about z, else the identity. World position of a
  /// local point: local * axis() + origin().
  Mat3 axis() const;
};

/// A parsed .map file.
struct MapFile {
  /// The name given to the parser (used in errors).
  std::string fileName;
  /// The file's Version number.
  int version = 2;
  /// The entities in file order (entity 0: worldspawn).
  std::vector<MapEntity> entities;
  /// The geometry CRC (line 3 of the .cm files written for this map).
  std::uint32_t geometryCrc = 0;

  /// The index of an entity: "#N" for entity N (0 is the worldspawn), else
  /// the first entity whose "name" key is exactly `nameOrIndex`. An Error
  /// naming it when there is none.
  Result<std::size_t> findEntity(std::string_view nameOrIndex) const;
};

/// Parses map text. `fileName` is used in error messages.
Result<MapFile> parseMapText(std::string_view text, std::string fileName = "<map>");
/// Reads and parses a .map file.
Result<MapFile> loadMapFile(const std::string& path);

/// Moves the world's geometry (the worldspawn entity's brush planes and patch
/// points) by `offset`, to build the same world far from the origin (the
/// large-world checks of docs/reliability.md). Other entities keep their
/// geometry and origins; the geometry CRC is left as it was read.
void moveWorldGeometry(MapFile& map, const Vec3& offset);

}  // namespace cmkit
