// Internal: the geometry CRC of a parsed map (line 3 of .cm files).
#pragma once

#include <cstdint>
#include <string_view>

#include "cmkit/map.h"

namespace cmkit::detail {

/// The raw IEEE-754 bits of a float (the original's float "CRC").
std::uint32_t floatCrc(float value);
/// The material-name hash: XOR over bytes c at index i (as signed char) of
/// c << (i & 3).
std::uint32_t stringCrc(std::string_view text);
/// The CRC of one brush: per side, the bits of a, b, c, d (d = -dist) XOR
/// the material hash.
std::uint32_t brushCrc(const MapBrush& brush);
/// The CRC of one patch: horz ^ vert subdivisions, the bits of every control
/// point's x, y, z, and the material hash.
std::uint32_t patchCrc(const MapPatch& patch);
/// XOR of the CRCs of all primitives of all entities.
std::uint32_t geometryCrc(const MapFile& map);

}  // namespace cmkit::detail
