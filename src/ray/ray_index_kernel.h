// ray_index_kernel.h: the walk through a RayIndex and its polygon tests,
// written once and compiled twice: in ray_index.cpp for every processor, and
// in ray_index_avx2.cpp with AVX2 for the processors that have it
// (RayIndex::cast() picks one; see cmkit/ray_index.h for the contract).
//
// WHY IT LOOKS LIKE C: the AVX2 translation unit is compiled with -mavx2.
// Any inline function of another header it called (Vec3::dot, std::array's
// operator[], ...) could be emitted there out of line, compiled for AVX2, and
// the linker may keep that copy for the whole program, which would then fail
// on a processor without AVX2 (in unoptimised builds this is the rule, not a
// risk). So the code here reads struct fields and plain arrays, calls only
// compiler builtins and its own `static` functions (one private copy per
// translation unit), and does the float arithmetic in the same order as the
// Vec3 / Pluecker functions would, so that both copies answer bit for bit
// alike.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ray/ray_index_layout.h"

namespace cmkit::detail {

// FLOAT ON PURPOSE: the node test works on float lanes (RayLayout::Node's
// boxes, Ray::inv, the entry distances) whatever Real is; the node boxes are
// padded relative to their magnitude (tol::kRayNodePadding), far beyond the
// rounding of a double build's coordinates to float. The polygon tests are
// in Real.

/// What the walk reads of a RayIndex.
struct Arrays {
  const RayLayout::Node* nodes;
  const RayLayout::Leaf* leaves;
  const RayLayout::Polygon* polygons;
  const RayLayout::EdgeLine* edges;
  const RayLayout::PolygonDetail* details;
};

/// A ray in the model's space with its per-ray constants. The near face of
/// each axis is the min or the max depending on the direction's sign:
/// nearRow / farRow are the byte offsets of those rows in a Node. The
/// reciprocals are finite, so no slab product is NaN.
struct Ray {
  Real start[3];
  Real end[3];
  Real dir[3];   ///< end - start
  Real line[6];  ///< Pluecker coordinates of the ray (Pluecker::fromRay)
  float inv[3];  ///< 1 / dir, finite
  std::size_t nearRow[3], farRow[3];
  std::uint32_t mask;
};

/// The first crossing found: where, and the polygon's position in the
/// index's polygon array (-1: none).
struct Crossing {
  Real t;
  std::int32_t slot;
};

/// The walk with the node test of ray_index.cpp (SSE2 on x86-64).
Crossing castBaseline(const Arrays& index, const Ray& ray);
/// The walk with the AVX2 node test (ray_index_avx2.cpp); call it only when
/// the processor has AVX2 (RayIndex::usesAvx2()). A build without the
/// kernel defines it as castBaseline.
Crossing castAvx2(const Arrays& index, const Ray& ray);

/// Rays walked together by castPacketAvx2: one per AVX2 float lane.
constexpr unsigned kPacket = 8;
/// Walks `count` (1 to kPacket) rays of one content mask together through
/// the index: a node's children are tested against every ray of the packet
/// that reached it, a leaf's polygons against all of those rays (the plane
/// and edge tests of testPolygon, eight rays per instruction). out[k] is what castAvx2(index, rays[k])
/// returns, bit for bit: a ray's answer is the first crossing (ties: the lower polygon index) of all the
/// polygons that accept it, whatever order they are tested in, and every node test lets through each box
/// holding such a crossing before the ray's best so far (the boxes are padded beyond the slab tests'
/// rounding). Only with AVX2 and FMA (as castAvx2).
void castPacketAvx2(const Arrays& index, const Ray* rays, unsigned count, Crossing* out);

/// Binary-hierarchy depth the index's builder never exceeds (it sizes the
/// walk's stack; an 8-wide node spans at least one binary level).
constexpr int kMaxDepth = 68;

/// A child waiting on the walk's stack.
struct Pending {
  std::uint32_t ref;
  float t;  ///< where the ray enters the child's box
};

/// Whether the sign bit of x is set (as signBitSet(float); -0 counts).
static inline bool signBit(float x) {
  std::uint32_t bits;
  __builtin_memcpy(&bits, &x, sizeof bits);
  return (bits >> 31) != 0;
}
/// The same for a double build's products.
static inline bool signBit(double x) {
  std::uint64_t bits;
  __builtin_memcpy(&bits, &x, sizeof bits);
  return (bits >> 63) != 0;
}

/// Whether the ray passes inside every edge of the polygon in `slot` (the
/// sign of each edge line's product with the ray's line).
static inline bool insideEdges(const Arrays& index, std::uint32_t slot, const Ray& r) {
  const RayLayout::Polygon& p = index.polygons[slot];
  const RayLayout::EdgeLine* lines = index.edges + p.firstEdge;
  const Real* ray = r.line;
  for (std::uint32_t j = 0; j < p.numEdges; ++j) {
    const Real* l = lines[j].p;
    const Real product =
        l[0] * ray[4] + l[1] * ray[5] + l[2] * ray[3] + l[4] * ray[0] + l[5] * ray[1] + l[3] * ray[2];
    if (lines[j].reversed ^ std::uint32_t(signBit(product))) return false;  // outside this edge
  }
  return true;
}

/// Whether a crossing at t of the polygon in `slot` may replace `best`: not
/// beyond it, and at the same t only from a lower polygon index.
static inline bool notBeyondBest(const Arrays& index, std::uint32_t slot, Real t, const Crossing& best,
                                 std::int32_t bestIndex) {
  return !(t > best.t || (t == best.t && index.polygons[slot].index > bestIndex));
}

/// The last part of acceptCrossing, for a crossing at t inside every edge
/// of the polygon in `slot` and not beyond the best: keeps it as `best`
/// when it lies in the polygon's acceptance box.
static inline void keepCrossing(const Arrays& index, std::uint32_t slot, const Ray& r, Real t, Crossing& best,
                                std::int32_t& bestIndex) {
  const Bounds& box = index.details[slot].acceptBox;
  const Real x = r.start[0] + r.dir[0] * t, y = r.start[1] + r.dir[1] * t, z = r.start[2] + r.dir[2] * t;
  if (x < box.min.x || y < box.min.y || z < box.min.z || x > box.max.x || y > box.max.y || z > box.max.z)
    return;
  best.t = t;
  best.slot = std::int32_t(slot);
  bestIndex = index.polygons[slot].index;
}

/// The second half of testPolygon: the ray crosses the plane of the
/// polygon in `slot` at t (front face, start not behind, end not in front);
/// keeps it as `best` when it is not beyond the best so far and the polygon
/// accepts it (inside every edge, within the acceptance box).
static inline void acceptCrossing(const Arrays& index, std::uint32_t slot, const Ray& r, Real t,
                                  Crossing& best, std::int32_t& bestIndex) {
  if (notBeyondBest(index, slot, t, best, bestIndex) && insideEdges(index, slot, r))
    keepCrossing(index, slot, r, t, best, bestIndex);
}

/// Tests one polygon (by slot), keeping `best` the first crossing; equal
/// crossings go to the lower model polygon index (`bestIndex`).
static inline void testPolygon(const Arrays& index, std::uint32_t slot, const Ray& r, Crossing& best,
                               std::int32_t& bestIndex) {
  const RayLayout::Polygon& p = index.polygons[slot];
  const Vec3& n = p.normal;
  if (!(n.x * r.dir[0] + n.y * r.dir[1] + n.z * r.dir[2] < 0)) return;  // only front faces
  const Real d1 = n.x * r.start[0] + n.y * r.start[1] + n.z * r.start[2] - p.dist;
  if (d1 < 0) return;  // starts behind
  const Real d2 = n.x * r.end[0] + n.y * r.end[1] + n.z * r.end[2] - p.dist;
  if (d2 > 0) return;  // ends in front
  const Real denom = d1 - d2;
  if (!(denom > 0)) return;
  acceptCrossing(index, slot, r, d1 / denom, best, bestIndex);
}

/// The walk: front to back, nearest child first, children entered beyond
/// the best crossing so far skipped. `enteredChildren(node, ray, best,
/// entry)` returns the children (bit k for child k) the ray enters before
/// `best` that hold contents of the mask, with where it enters each box in
/// `entry`.
template <class EnteredChildren>
static Crossing walk(const Arrays& index, const Ray& r, EnteredChildren enteredChildren) {
  constexpr int kWidth = RayLayout::kWidth;
  Crossing best{1, -1};
  std::int32_t bestIndex = 0x7fffffff;
  // At most kWidth - 1 children wait per level, and a node sorts its
  // children in the kWidth slots above the top.
  Pending stack[(kWidth - 1) * kMaxDepth + kWidth];
  std::size_t sp = 0;
  std::uint32_t ref = 0;
  for (;;) {
    if (ref & RayLayout::kLeaf) {
      const RayLayout::Leaf& leaf = index.leaves[ref & ~RayLayout::kLeaf];
      for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i)
        if (index.polygons[i].contents & r.mask) testPolygon(index, i, r, best, bestIndex);
    } else {
      const RayLayout::Node& n = index.nodes[ref];
      alignas(32) float entry[kWidth];
      const auto hits = unsigned(enteredChildren(n, r, float(best.t), entry));
      if (hits) {
        const int first = __builtin_ctz(hits);
        const unsigned rest = hits & (hits - 1);
        if (rest == 0) {  // one child: no ordering
          ref = n.child[first];
          continue;
        }
        if ((rest & (rest - 1)) == 0) {  // two: the farther one waits
          const int second = __builtin_ctz(rest);
          const bool swap = entry[second] < entry[first];
          const int near = swap ? second : first, far = swap ? first : second;
          stack[sp++] = Pending{n.child[far], entry[far]};
          ref = n.child[near];
          continue;
        }
        // More: insertion-sorted in place above the top of the stack,
        // farthest first; all but the nearest wait. (In place, not in a
        // local array copied over: the compiler turns that copy into a
        // memcpy call, which cost a fifth of the whole cast.)
        Pending* order = stack + sp;
        std::size_t count = 0;
        for (unsigned bits = hits; bits; bits &= bits - 1) {
          const int k = __builtin_ctz(bits);
          const Pending p{n.child[k], entry[k]};
          std::size_t j = count++;
          for (; j > 0 && order[j - 1].t < p.t; --j) order[j] = order[j - 1];
          order[j] = p;
        }
        sp += count - 1;
        ref = stack[sp].ref;
        continue;
      }
    }
    // Next waiting child that may still hold a nearer crossing.
    for (;;) {
      if (sp == 0) return best;
      const Pending p = stack[--sp];
      if (p.t <= best.t) {
        ref = p.ref;
        break;
      }
    }
  }
}

}  // namespace cmkit::detail
