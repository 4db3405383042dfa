// cmkit — collision models for id Tech 4 style level geometry.
//
// config.h: the scalar type and the library version.
//
// Storage and arithmetic are 32-bit float by default, like the original Doom 3
// code, so that results can be compared bit for bit with it. A build with
// -DCMKIT_DOUBLE=ON makes Real a 64-bit double: far from the origin (tens of
// thousands of units) float's spacing makes sweeps drift; double keeps them
// exact to far smaller distances (docs/reliability.md, "Large worlds"). The
// .cm format, the map CRC and the original's reciprocal square root stay
// float wherever the original's bits matter; code that depends on float bit
// patterns says so where it does.
#pragma once

#include "cmkit/version.h"  // generated: the version numbers and CMKIT_DOUBLE

namespace cmkit {

// CMKIT_DOUBLE (cmkit/version.h) is 1 in a double-precision build, 0
// otherwise; code written for float lanes (SSE paths) tests it with #if.
#if CMKIT_DOUBLE
/// The scalar type of all geometry (this build: double, -DCMKIT_DOUBLE=ON).
using Real = double;
#else
/// The scalar type of all geometry (this build: float, as the original).
using Real = float;
#endif

/// True in a double-precision build (-DCMKIT_DOUBLE=ON).
inline constexpr bool kDoublePrecision = sizeof(Real) == sizeof(double);

/// Library version (semantic versioning; project(VERSION) in CMakeLists.txt,
/// through the generated cmkit/version.h).
inline constexpr int kVersionMajor = CMKIT_VERSION_MAJOR;
/// Minor version (0.x: the API may change between minor versions; CHANGELOG.md).
inline constexpr int kVersionMinor = CMKIT_VERSION_MINOR;
/// Patch version.
inline constexpr int kVersionPatch = CMKIT_VERSION_PATCH;
/// "MAJOR.MINOR.PATCH".
inline constexpr const char* kVersionString = CMKIT_VERSION_STRING;

}  // namespace cmkit
