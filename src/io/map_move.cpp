// moveWorldGeometry (cmkit/map.h): the worldspawn's primitives moved.
#include <variant>

#include "cmkit/map.h"

namespace cmkit {

void moveWorldGeometry(MapFile& map, const Vec3& offset) {
  if (map.entities.empty()) return;
  for (MapPrimitive& primitive : map.entities.front().primitives) {
    if (auto* brush = std::get_if<MapBrush>(&primitive)) {
      // n.p = dist for the old points, so n.(p + offset) = dist + n.offset.
      for (MapBrushSide& side : brush->sides) side.plane.dist += side.plane.normal.dot(offset);
    } else {
      for (Vec3& p : std::get<MapPatch>(primitive).points) p = p + offset;
    }
  }
}

}  // namespace cmkit
