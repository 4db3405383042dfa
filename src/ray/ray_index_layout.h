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

/// The layout of a RayIndex: its nodes, leaves, polygons and edge lines.
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

  /// A leaf: a run of polygons.
  struct Leaf {
    std::uint32_t first = 0;
    std::uint32_t count = 0;
  };
  /// What the crossing test needs of a polygon, in leaf order (32 bytes).
  struct Polygon {
    Vec3 normal;
    Real dist = 0;
    std::uint32_t contents = 0;
    std::int32_t index = 0;  ///< in the model
    std::uint32_t firstEdge = 0;
    std::uint32_t numEdges = 0;
  };
  /// What is read only for a polygon that accepts a crossing.
  struct PolygonDetail {
    Bounds acceptBox;  ///< where the polygon accepts a crossing
    std::int32_t material = -1;
  };
  /// An edge line of a polygon, in the model's stored direction, and whether
  /// the polygon uses it reversed.
  struct EdgeLine {
    Real p[6];
    std::uint32_t reversed;
  };
};

}  // namespace cmkit::detail
