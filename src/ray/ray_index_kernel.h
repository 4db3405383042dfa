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

#if defined(__SSE2__) && !defined(CMKIT_NO_SIMD) && !CMKIT_DOUBLE
#include <emmintrin.h>
#endif

namespace cmkit::detail {

// FLOAT ON PURPOSE: the node test works on float lanes (RayLayout::Node's
// boxes, Ray::inv, the entry distances) whatever Real is; the node boxes are
// padded relative to their magnitude (tol::kRayNodePadding), far beyond the
// rounding of a double build's coordinates to float. The polygon tests are
// in Real.

/// What the walk reads of a RayIndex.
struct Arrays {
  const RayLayout::Node* nodes;
  const RayLayout::LeafChunk* leafChunks;
  const RayLayout::PolygonRecord* records;
};

/// A ray in the model's space with its per-ray constants. The near face of
/// each axis is the min or the max depending on the direction's sign:
/// nearRow / farRow are the byte offsets of those rows in a Node. The
/// reciprocals are finite, so no slab product is NaN. (Each vector has a
/// fourth element, unused, so that a cast's set-up writes it with one
/// 16-byte store.)
struct Ray {
  alignas(16) Real start[4];
  alignas(16) Real end[4];
  alignas(16) Real dir[4];             ///< end - start
  alignas(16) float inv[4];            ///< 1 / dir, finite
  alignas(16) float startTimesInv[4];  ///< float(start) * inv (the AVX2 node tests')
  Real line[6];                        ///< Pluecker coordinates of the ray (rayLine); set for packets only
  std::size_t nearRow[3], farRow[3];   ///< single casts only
  std::uint32_t mask;
};

/// The Pluecker coordinates of the line start -> start + dir, by the
/// arithmetic of Pluecker::fromRay (so the same values). A single cast makes
/// them only when a leaf's plane is crossed (most casts never get there);
/// a packet's rays have them in Ray::line.
static inline void rayLine(const Real* s, const Real* dir, Real* line) {
  line[0] = s[0] * dir[1] - s[1] * dir[0];
  line[1] = s[0] * dir[2] - s[2] * dir[0];
  line[2] = -dir[0];
  line[3] = s[1] * dir[2] - s[2] * dir[1];
  line[4] = -dir[2];
  line[5] = dir[1];
}

/// The first crossing found: where, the polygon's position in the index's
/// records array (-1: none), and its leaf (child reference), lane and side
/// (twin: the lane's twin), where its plane and contents are.
struct Crossing {
  Real t;
  std::int32_t slot;
  std::uint32_t leaf;
  std::uint32_t lane;
  bool twin;
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
/// and edge tests of testLeaf's lanes, eight rays per instruction). out[k] is what castAvx2(index, rays[k])
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

/// The leaf of a child reference: its head (its corner rows follow it) and
/// how many of its lanes hold a polygon.
static inline const RayLayout::LeafHead& leafHead(const Arrays& index, std::uint32_t ref) {
  const std::uint32_t chunk = (ref & ~RayLayout::kLeaf) >> RayLayout::kLeafCountBits;
  return *reinterpret_cast<const RayLayout::LeafHead*>(index.leafChunks + chunk);
}
static inline std::uint32_t leafCount(std::uint32_t ref) { return (ref & (RayLayout::kLeafLanes - 1)) + 1; }
static inline const RayLayout::CornerRow* cornerRows(const RayLayout::LeafHead& head) {
  return reinterpret_cast<const RayLayout::CornerRow*>(&head + 1);
}

/// Edge j of a leaf's lanes: the corner rows it runs from and to (the last
/// edge to the leaf's closing row).
struct EdgeCorners {
  const RayLayout::CornerRow* from;
  const RayLayout::CornerRow* to;
};
static inline EdgeCorners edgeCorners(const RayLayout::LeafHead& head, std::uint32_t j) {
  const RayLayout::CornerRow* rows = cornerRows(head);
  return {rows + j, rows + (j + 1 == head.numEdges ? head.closingRow : j + 1)};
}

/// Whether lane k's polygon uses the edge reversed (0 or 1).
static inline std::uint32_t edgeReversed(const EdgeCorners& e, std::uint32_t k) {
  return (e.from->reversed >> k) & 1u;
}

/// The line from lane k's corner in row `s` to its corner in row `e`, by
/// Pluecker::fromLine's arithmetic.
static inline void lineOfCorners(const RayLayout::CornerRow& s, const RayLayout::CornerRow& e,
                                 std::uint32_t k, Real* l) {
  const Real sx = s.v[0][k], sy = s.v[1][k], sz = s.v[2][k];
  const Real ex = e.v[0][k], ey = e.v[1][k], ez = e.v[2][k];
  l[0] = sx * ey - ex * sy;
  l[1] = sx * ez - ex * sz;
  l[2] = sx - ex;
  l[3] = sy * ez - ey * sz;
  l[4] = sz - ez;
  l[5] = ey - sy;
}

/// The line of lane k's edge (Pluecker coordinates), made from its two
/// corners from the edge's first vertex to its second: the model's line of
/// the edge, bit for bit.
static inline void edgeLine(const EdgeCorners& e, std::uint32_t k, Real* l) {
  if (edgeReversed(e, k))
    lineOfCorners(*e.to, *e.from, k, l);
  else
    lineOfCorners(*e.from, *e.to, k, l);
}

/// The line from lane k's corner the edge runs from to the one it runs to:
/// edgeLine's, or where the polygon uses the edge reversed, its every
/// coordinate negated exactly (x - y is -(y - x) in IEEE arithmetic) up to
/// the sign of a zero. So its product with a ray's line (edgeProduct) is
/// the model's negated exactly, rounding to nearest being symmetric, unless
/// it is zero: its sign bit is the "outside" answer of outsideEdge wherever
/// it is not zero.
static inline void cornerLine(const EdgeCorners& e, std::uint32_t k, Real* l) {
  lineOfCorners(*e.from, *e.to, k, l);
}

/// The product of an edge's line with a ray's line (the order of
/// Pluecker::permutedInnerProduct): its sign says on which side of the
/// edge the ray passes.
static inline Real edgeProduct(const Real* edge, const Real* ray) {
  return edge[0] * ray[4] + edge[1] * ray[5] + edge[2] * ray[3] + edge[4] * ray[0] + edge[5] * ray[1] +
         edge[3] * ray[2];
}

/// 1 when the ray of Pluecker coordinates `line` passes outside lane k's
/// edge (the sign of the product is not the one the polygon's use of the
/// edge asks), else 0.
static inline std::uint32_t outsideEdge(const EdgeCorners& e, std::uint32_t k, const Real* line) {
  Real edge[6];
  edgeLine(e, k, edge);
  return edgeReversed(e, k) ^ std::uint32_t(signBit(edgeProduct(edge, line)));
}

/// outsideEdge for the four lanes at once (bit k: lane k).
static inline std::uint32_t outsideEdgesLaneByLane(const EdgeCorners& e, const Real* line) {
  std::uint32_t outside = 0;
  for (std::uint32_t k = 0; k < RayLayout::kLeafLanes; ++k) outside |= outsideEdge(e, k, line) << k;
  return outside;
}
#if defined(__SSE2__) && !defined(CMKIT_NO_SIMD) && !CMKIT_DOUBLE
/// The same with SSE2 float lanes, without picking each lane's first
/// vertex: every lane's line is cornerLine's, whose product's sign bit is
/// outsideEdge's answer in every lane, reversed or not, where no product
/// is zero; where one is (the ray meets an edge's line), the lanes are
/// tested one by one, as the model's lines would be.
/// (Only the lanes of `live` count: an empty lane's product is zero.)
static inline std::uint32_t outsideEdges(const EdgeCorners& e, const Real* line, std::uint32_t live) {
  static_assert(RayLayout::kLeafLanes == 4);
  const RayLayout::CornerRow& a = *e.from;
  const RayLayout::CornerRow& b = *e.to;
  const __m128 sx = _mm_loadu_ps(a.v[0]), sy = _mm_loadu_ps(a.v[1]), sz = _mm_loadu_ps(a.v[2]);
  const __m128 ex = _mm_loadu_ps(b.v[0]), ey = _mm_loadu_ps(b.v[1]), ez = _mm_loadu_ps(b.v[2]);
  // (Lambdas, not the intrinsics' addresses: they have no out-of-line
  // definition to point to, which an unoptimised build asks for.)
  const auto mul = [](__m128 x, __m128 y) { return _mm_mul_ps(x, y); };
  const auto sub = [](__m128 x, __m128 y) { return _mm_sub_ps(x, y); };
  // lineOfCorners' arithmetic, and edgeProduct's.
  const auto term = [&](__m128 l, int r) { return mul(l, _mm_set1_ps(line[r])); };
  __m128 p = _mm_add_ps(term(sub(mul(sx, ey), mul(ex, sy)), 4), term(sub(mul(sx, ez), mul(ex, sz)), 5));
  p = _mm_add_ps(p, term(sub(sx, ex), 3));
  p = _mm_add_ps(p, term(sub(sz, ez), 0));
  p = _mm_add_ps(p, term(sub(ey, sy), 1));
  p = _mm_add_ps(p, term(sub(mul(sy, ez), mul(ey, sz)), 2));
  if (std::uint32_t(_mm_movemask_ps(_mm_cmpeq_ps(p, _mm_setzero_ps()))) & live) [[unlikely]]
    return outsideEdgesLaneByLane(e, line);
  return std::uint32_t(_mm_movemask_ps(p));
}
#else
static inline std::uint32_t outsideEdges(const EdgeCorners& e, const Real* line, std::uint32_t) {
  return outsideEdgesLaneByLane(e, line);
}
#endif

/// Whether a packet's ray passes inside every edge of the polygon in `lane`
/// of the leaf (the sign of each edge line's product with the ray's line),
/// or with `twin` inside every edge of the lane's twin (outside every edge
/// of the lane's polygon: RayLayout::LeafHead::twins).
static inline bool insideEdges(const RayLayout::LeafHead& head, std::uint32_t lane, const Ray& r, bool twin) {
  for (std::uint32_t j = 0; j < head.numEdges; ++j)
    if (outsideEdge(edgeCorners(head, j), lane, r.line) != std::uint32_t(twin)) return false;
  return true;
}

/// The records[] index of the twin of lane k of the leaf `ref` (bit k of
/// head.twins set): after the leaf's lanes, one per twin in lane order.
static inline std::uint32_t twinRecord(const RayLayout::LeafHead& head, std::uint32_t ref, std::uint32_t k) {
  return head.firstRecord + leafCount(ref) + std::uint32_t(__builtin_popcount(head.twins & ((1u << k) - 1)));
}

/// Whether a crossing at t of the polygon of record `rec` may replace
/// `best`: not beyond it, and at the same t only from a lower polygon index.
static inline bool notBeyondBest(const Arrays& index, std::uint32_t rec, Real t, const Crossing& best) {
  return !(t > best.t ||
           (t == best.t && best.slot >= 0 && index.records[rec].index > index.records[best.slot].index));
}

/// The last part of a polygon's test, for a crossing at t inside every
/// edge of lane k's polygon of the leaf `ref` (or with `twin` its twin's),
/// of record `rec` and not beyond the best: keeps it as `best` when it
/// lies in the polygon's acceptance box.
static inline void keepCrossing(const Arrays& index, std::uint32_t ref, std::uint32_t k, bool twin,
                                std::uint32_t rec, const Ray& r, Real t, Crossing& best) {
  const Bounds& box = index.records[rec].acceptBox;
  const Real x = r.start[0] + r.dir[0] * t, y = r.start[1] + r.dir[1] * t, z = r.start[2] + r.dir[2] * t;
  if (x < box.min.x || y < box.min.y || z < box.min.z || x > box.max.x || y > box.max.y || z > box.max.z)
    return;
  best = Crossing{t, std::int32_t(rec), ref, k, twin};
}

/// The plane part of the tests of lane k's polygon and of its twin: whether
/// the ray crosses the polygon's front face (`front`: front face, start not
/// behind, end not in front, a crossing) or its twin's (`back`: the same
/// with every sign reversed, which is what the twin's exactly negated plane
/// computes, whether or not the lane has a twin), and where (t, the same
/// for both; meaningful only then).
static inline void crossesPlanes(const RayLayout::LeafHead& h, std::uint32_t k, const Ray& r, Real& t,
                                 bool& front, bool& back) {
  const Real facing = h.x[k] * r.dir[0] + h.y[k] * r.dir[1] + h.z[k] * r.dir[2];
  const Real d1 = h.x[k] * r.start[0] + h.y[k] * r.start[1] + h.z[k] * r.start[2] - h.dist[k];
  const Real d2 = h.x[k] * r.end[0] + h.y[k] * r.end[1] + h.z[k] * r.end[2] - h.dist[k];
  const Real denom = d1 - d2;
  t = d1 / denom;
  front = (facing < 0) & !(d1 < 0) & !(d2 > 0) & (denom > 0);
  back = (facing > 0) & !(d1 > 0) & !(d2 < 0) & (denom < 0);
}

/// Tests the polygons of a leaf (reference `ref`), keeping `best` the first
/// crossing; equal crossings go to the lower model polygon index
/// (notBeyondBest). Every step on all lanes alike, as plain lane loops
/// without branches (the compiler may make them SIMD): the planes and
/// contents, then, while some lane is left, the edges. A lane's answer
/// is that of testing its polygon alone (the same operations in the same
/// order; for its twin the same values with their signs reversed), and the
/// best kept is the first crossing, lowest index on ties, whatever the
/// order, so a leaf answers as its polygons tested one by one.
static inline void testLeaf(const Arrays& index, std::uint32_t ref, const Ray& r, Crossing& best) {
  constexpr std::uint32_t kLanes = RayLayout::kLeafLanes;
  const RayLayout::LeafHead& h = leafHead(index, ref);
  Real t[kLanes];
  std::uint32_t lanes = 0, twinLanes = 0;  // bit k: lane k's polygon / its twin still a candidate
  for (std::uint32_t k = 0; k < kLanes; ++k) {
    bool front, back;
    crossesPlanes(h, k, r, t[k], front, back);
    const bool open = ((h.contents[k] & r.mask) != 0) & !(t[k] > best.t);
    lanes |= std::uint32_t(front & open) << k;
    twinLanes |= std::uint32_t(back & open) << k;
  }
  twinLanes &= h.twins;
  if (!(lanes | twinLanes)) return;
  // The first candidate's record is read if it passes its edges: its load
  // overlaps the edge tests.
  __builtin_prefetch(index.records + (lanes ? h.firstRecord + __builtin_ctz(lanes)
                                            : twinRecord(h, ref, std::uint32_t(__builtin_ctz(twinLanes)))));
  Real line[6];
  rayLine(r.start, r.dir, line);
  for (std::uint32_t j = 0; j < h.numEdges && (lanes | twinLanes); ++j) {
    const std::uint32_t outside = outsideEdges(edgeCorners(h, j), line, lanes | twinLanes);
    lanes &= ~outside;
    twinLanes &= outside;  // a twin is inside where the lane's polygon is outside
  }
  for (; lanes; lanes &= lanes - 1) {
    const auto k = std::uint32_t(__builtin_ctz(lanes));
    const std::uint32_t rec = h.firstRecord + k;
    if (notBeyondBest(index, rec, t[k], best)) keepCrossing(index, ref, k, false, rec, r, t[k], best);
  }
  for (; twinLanes; twinLanes &= twinLanes - 1) {
    const auto k = std::uint32_t(__builtin_ctz(twinLanes));
    const std::uint32_t rec = twinRecord(h, ref, k);
    if (notBeyondBest(index, rec, t[k], best)) keepCrossing(index, ref, k, true, rec, r, t[k], best);
  }
}

/// Asks for the first two cache lines of a child that waits on the walk's
/// stack, so that they are in the cache when the walk comes back to it (a
/// node's or a leaf head's lines are what its test reads first). Always
/// inlined: GCC finds a function that only prefetches free of side effects
/// and drops its calls (an earlier prefetchChildren never ran: no prefetch
/// instruction in the walk's code).
__attribute__((always_inline)) static inline void prefetchChild(const Arrays& index, std::uint32_t ref) {
  const char* p = (ref & RayLayout::kLeaf) ? reinterpret_cast<const char*>(&leafHead(index, ref))
                                           : reinterpret_cast<const char*>(index.nodes + ref);
  __builtin_prefetch(p);
  __builtin_prefetch(p + 64);
}

/// The walk: front to back, nearest child first, children entered beyond
/// the best crossing so far skipped. `enteredChildren(node, ray, best,
/// entry)` returns the children (bit k for child k) the ray enters before
/// `best` that hold contents of the mask, with where it enters each box in
/// `entry`.
template <class EnteredChildren>
static Crossing walk(const Arrays& index, const Ray& r, EnteredChildren enteredChildren) {
  constexpr int kWidth = RayLayout::kWidth;
  Crossing best{1, -1, 0, 0, false};
  // At most kWidth - 1 children wait per level, and a node sorts its
  // children in the kWidth slots above the top.
  Pending stack[(kWidth - 1) * kMaxDepth + kWidth];
  std::size_t sp = 0;
  std::uint32_t ref = 0;
  for (;;) {
    if (ref & RayLayout::kLeaf) {
      testLeaf(index, ref, r, best);
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
          prefetchChild(index, n.child[far]);
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
          prefetchChild(index, p.ref);
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
