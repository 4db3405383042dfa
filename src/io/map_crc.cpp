// The map geometry CRC (include/cmkit/map.h; line 3 of a .cm file, docs/cm-format.md).
#include "io/map_crc.h"

#include <type_traits>

#include "cmkit/vec3.h"

namespace cmkit::detail {

std::uint32_t floatCrc(float value) { return floatBits(value); }

std::uint32_t stringCrc(std::string_view text) {
  std::uint32_t crc = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    // The byte as a signed char, promoted to int, shifted: bytes >= 0x80 set
    // the high bits, as in the original.
    const int c = static_cast<signed char>(text[i]);
    crc ^= static_cast<std::uint32_t>(c) << (i & 3);
  }
  return crc;
}

std::uint32_t brushCrc(const MapBrush& brush) {
  std::uint32_t crc = 0;
  for (const MapBrushSide& side : brush.sides) {
    crc ^= floatCrc(side.plane.normal.x);
    crc ^= floatCrc(side.plane.normal.y);
    crc ^= floatCrc(side.plane.normal.z);
    crc ^= floatCrc(-side.plane.dist);  // the file's d: negation is exact
    crc ^= stringCrc(side.material);
  }
  return crc;
}

std::uint32_t patchCrc(const MapPatch& patch) {
  std::uint32_t crc = static_cast<std::uint32_t>(patch.horzSubdivisions ^ patch.vertSubdivisions);
  for (const Vec3& p : patch.points) {
    crc ^= floatCrc(p.x);
    crc ^= floatCrc(p.y);
    crc ^= floatCrc(p.z);
  }
  crc ^= stringCrc(patch.material);
  return crc;
}

std::uint32_t geometryCrc(const MapFile& map) {
  std::uint32_t crc = 0;
  for (const MapEntity& entity : map.entities) {
    for (const MapPrimitive& primitive : entity.primitives) {
      crc ^= std::visit(
          [](const auto& prim) -> std::uint32_t {
            if constexpr (std::is_same_v<std::decay_t<decltype(prim)>, MapBrush>) {
              return brushCrc(prim);
            } else {
              return patchCrc(prim);
            }
          },
          primitive);
    }
  }
  return crc;
}

}  // namespace cmkit::detail
