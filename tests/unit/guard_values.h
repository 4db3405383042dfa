// Values at and past the query guards' limits, for the tests that set every
// float of a query to each in turn (test_query_guards.cpp,
// test_query_point_contents.cpp).
#pragma once

#include <cmath>
#include <limits>
#include <vector>

#include "cmkit/tolerances.h"
#include "cmkit/vec3.h"

namespace cmkit::test {

/// For a coordinate: the range's limit and the next float past it, either
/// sign; infinities, NaN, -0 and 0, and two plain values.
inline std::vector<Real> rangeEdgeValues() {
  const Real lim = tol::kMaxQueryCoordinate, inf = std::numeric_limits<Real>::infinity();
  const Real past = std::nextafter(lim, inf);
  return {lim,      -lim,    past, -past, inf, -inf, std::numeric_limits<Real>::quiet_NaN(),
          -Real(0), Real(0), 5,    -5};
}

/// For an axis element: -0 and 0, 1 and its neighbours, -1, the smallest
/// subnormals, a half and NaN.
inline std::vector<Real> axisEdgeValues() {
  return {Real(0),
          -Real(0),
          1,
          -1,
          std::nextafter(Real(1), Real(2)),
          std::nextafter(Real(1), Real(0)),
          std::numeric_limits<Real>::denorm_min(),
          -std::numeric_limits<Real>::denorm_min(),
          Real(0.5),
          std::numeric_limits<Real>::quiet_NaN()};
}

}  // namespace cmkit::test
