// Internal: a polygon's reversed twin, the other side of a two-sided surface
// (the builder adds a reversed copy of every polygon of a two-sided
// material, as the original does). The query layouts that sort polygons
// (the polygons' hierarchy, polygon_bvh.h; the ray index) keep a pair as one
// entry whose two sides are told apart by the sign of one product.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/model.h"

namespace cmkit::detail {

/// Whether polygon b is polygon a's reversed twin: the same contents, the
/// plane negated exactly (sign of zero included: every product of a plane
/// test is then exactly negated) and the same edges used the other way
/// round (so "inside every edge of b" is "outside every edge of a" for the
/// same products).
bool isTwin(const ModelArrays& m, const CmPolygon& a, const CmPolygon& b);

/// Where a builder's reversed copy starts: the s for which edge list `b` is
/// `a`'s edges negated in reverse order from a[s] (b[k] == -a[(s + n - k)
/// mod n] for every k, n edges each), or -1 when there is none.
std::ptrdiff_t reversedFrom(std::span<const std::int32_t> a, std::span<const std::int32_t> b);

/// For each of `polygons` (model polygon numbers), the position in
/// `polygons` of its reversed twin (isTwin), or -1: neighbours in `polygons`
/// first, then pairs among the rest of the same edges (a hash of their
/// sorted edge numbers), each polygon in at most one pair, the first found.
std::vector<std::int32_t> findTwins(const ModelArrays& m, std::span<const std::uint32_t> polygons);

}  // namespace cmkit::detail
