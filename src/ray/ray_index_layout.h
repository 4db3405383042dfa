// ray_index_layout.h: how a RayIndex is stored (private to src/ray and the
// tests). The walk in ray_index_kernel.h reads it, so this header holds plain
// structs and constants only (see the AVX2 rule there).
//
// FLOAT ON PURPOSE: node boxes are float whatever Real is: one SIMD register
// row holds a coordinate of all eight children (the boxes are padded beyond
// what polygons accept, so their rounding costs nothing but a visit).
#pragma once

#include <cstdint>

#include "cmkit/bounds.h"
#include "cmkit/config.h"
#include "cmkit/vec3.h"

namespace cmkit::detail {

/// The layout of a RayIndex: its nodes, leaves and polygon records.
struct RayLayout {
  /// Children per node.
  static constexpr int kWidth = 8;
  /// A node of the hierarchy: eight children's boxes (structure of arrays, so
  /// that one SIMD test checks all eight), what they are and which contents
  /// they hold (256 bytes).
  struct alignas(64) Node {
    float min[3][kWidth];
    float max[3][kWidth];
    std::uint32_t child[kWidth];     ///< node index, or kLeaf | leaf index
    std::uint32_t contents[kWidth];  ///< OR of the contents below each child (0: empty slot)
  };
  static constexpr std::uint32_t kLeaf = 0x80000000u;

  /// Polygons per leaf at most: the lanes of a leaf's blocks.
  static constexpr std::uint32_t kLeafLanes = 4;
  /// A child reference to a leaf is kLeaf | chunk << kLeafCountBits |
  /// (count - 1): the leaf is stored from leafChunks[chunk] on (a LeafHead,
  /// then its CornerRows), its polygons are lanes 0 .. count - 1.
  static constexpr int kLeafCountBits = 2;
  static_assert(1u << kLeafCountBits == kLeafLanes);
  /// The unit leaves are stored in (a cache line).
  struct alignas(64) LeafChunk {
    unsigned char bytes[64];
  };
  /// A leaf's polygons side by side, lane k one polygon: their planes,
  /// contents, where their records start and how many edges their corner
  /// rows make. The walk tests every lane at once (no branch per polygon)
  /// from one run of memory that holds all it reads of a leaf (float
  /// builds: the head and a triangle leaf's corners in four cache lines),
  /// in place of a polygon record and edge lines elsewhere. Unused lanes
  /// have a zero normal (it faces no ray) and contents 0.
  ///
  /// A lane may also hold its polygon's reversed twin (bit k of `twins`):
  /// a polygon of the same contents whose plane is the lane's negated
  /// exactly and whose edges are the lane's used the other way round, as
  /// the two sides of a two-sided surface are. Its plane test is the
  /// lane's with every sign reversed and the same t, its edge test
  /// "outside every edge" of the lane's edges, so one lane tests both
  /// (a ray crosses at most one of them) in half the memory of two.
  struct LeafHead {
    Real x[kLeafLanes], y[kLeafLanes], z[kLeafLanes], dist[kLeafLanes];
    std::uint32_t contents[kLeafLanes];
    std::uint32_t firstRecord;  ///< records[] index of lane 0 (lane k: + k)
    std::uint32_t numEdges;     ///< the most edges of a lane's polygon: numEdges CornerRows follow, or
                                ///< numEdges + 1 with a closing row
    /// The row the last edge runs to: row numEdges (the closing row, a
    /// repeat of each lane's next corner), or row 0 when every lane's
    /// polygon's edge count divides numEdges (a leaf of triangles, say),
    /// so that going on from the last row to the first closes each lane's
    /// loop.
    std::uint32_t closingRow;
    /// Lanes holding a twin (bit k: lane k). The twins' records follow the
    /// lanes', in lane order (twinRecord in ray_index_kernel.h).
    std::uint32_t twins;
  };
  /// Corner j of each lane's polygon (v[c][k]: coordinate c of lane k),
  /// where its edge j starts in the polygon's order; edge j runs to corner
  /// j + 1 (the last edge to LeafHead::closingRow). The walk makes an
  /// edge's line from its two corners as the model's line of the edge is
  /// made (Pluecker::fromLine, from the edge's first vertex to its second:
  /// `reversed` says which corner that is), so the same line, bit for bit,
  /// in the bytes of one corner instead of a line's six coordinates. A
  /// polygon of n edges with fewer than the leaf's numEdges goes round
  /// again (corner j is its corner j mod n: the same tests again, so no
  /// other answer).
  struct CornerRow {
    Real v[3][kLeafLanes];
    /// Bit k: lane k's polygon uses edge j reversed (its second vertex is
    /// corner j). Unused in a closing row.
    std::uint32_t reversed;
  };
  static_assert(sizeof(LeafHead) % alignof(CornerRow) == 0, "the corner rows follow the head");
  /// What is read of a polygon beyond its leaf: where it accepts a crossing
  /// (read for a crossing inside its edges), and what the answer names
  /// (its plane and contents are its lane's, a twin's the lane's negated).
  /// 32 bytes in float builds, on a 32-byte boundary: one cache line, and
  /// the answer's read finds it in the cache.
  struct alignas(sizeof(Real) == 4 ? 32 : 8) PolygonRecord {
    Bounds acceptBox;        ///< where the polygon accepts a crossing
    std::int32_t index = 0;  ///< in the model
    std::int32_t material = -1;
  };
  static_assert(sizeof(Real) != 4 || sizeof(PolygonRecord) == 32);
};

}  // namespace cmkit::detail
