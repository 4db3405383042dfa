// cmkit — collision models for id Tech 4 style level geometry.
//
// config.h: the scalar type and the library version.
//
// Storage and arithmetic are 32-bit float, like the original Doom 3 code, so
// that results can be compared bit for bit with it. The scalar type lives
// behind one alias so that a double-precision build stays possible later;
// code that depends on float bit patterns (the map CRC, the original's
// reciprocal square root) says so where it does.
#pragma once

namespace cmkit {

/// The scalar type of all geometry.
using Real = float;

/// Library version (semantic versioning).
inline constexpr int kVersionMajor = 0;
inline constexpr int kVersionMinor = 1;
inline constexpr int kVersionPatch = 0;

}  // namespace cmkit
