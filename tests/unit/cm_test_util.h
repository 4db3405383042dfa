// Helpers for the .cm tests: comparing models field by field.
#pragma once

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "cmkit/cm_file.h"
#include "cmkit/model.h"

namespace cmkit::test {

/// Bitwise equality of two floats (so -0 != 0, as the files distinguish them).
inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
inline bool sameBits(const Vec3& a, const Vec3& b) {
  return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z);
}
inline bool sameBits(const Bounds& a, const Bounds& b) {
  return sameBits(a.min, b.min) && sameBits(a.max, b.max);
}
inline bool sameBits(const Plane& a, const Plane& b) {
  return sameBits(a.normal, b.normal) && sameBits(a.dist, b.dist);
}

/// Empty when the models are identical in every stored field; otherwise the
/// first difference.
inline std::string modelDifference(const ModelArrays& a, const ModelArrays& b) {
  if (a.name != b.name) return "name";
  if (!sameBits(a.bounds, b.bounds)) return "bounds";
  if (a.contents != b.contents) return "contents";
  if (a.vertices.size() != b.vertices.size()) return "vertex count";
  for (std::size_t i = 0; i < a.vertices.size(); ++i)
    if (!sameBits(a.vertices[i], b.vertices[i])) return "vertex " + std::to_string(i);
  if (a.edges.size() != b.edges.size()) return "edge count";
  for (std::size_t i = 0; i < a.edges.size(); ++i) {
    const CmEdge &x = a.edges[i], &y = b.edges[i];
    if (x.vertex[0] != y.vertex[0] || x.vertex[1] != y.vertex[1] || x.internal != y.internal ||
        x.numUsers != y.numUsers || !sameBits(x.normal, y.normal))
      return "edge " + std::to_string(i);
  }
  if (a.polygonEdges != b.polygonEdges) return "polygon edge lists";
  if (a.polygons.size() != b.polygons.size()) return "polygon count";
  for (std::size_t i = 0; i < a.polygons.size(); ++i) {
    const CmPolygon &x = a.polygons[i], &y = b.polygons[i];
    if (!sameBits(x.bounds, y.bounds) || !sameBits(x.plane, y.plane) || x.contents != y.contents ||
        a.materialName(x.material) != b.materialName(y.material) || x.firstEdge != y.firstEdge ||
        x.numEdges != y.numEdges)
      return "polygon " + std::to_string(i);
  }
  if (a.brushPlanes.size() != b.brushPlanes.size()) return "brush plane count";
  for (std::size_t i = 0; i < a.brushPlanes.size(); ++i)
    if (!sameBits(a.brushPlanes[i], b.brushPlanes[i])) return "brush plane " + std::to_string(i);
  if (a.brushes.size() != b.brushes.size()) return "brush count";
  for (std::size_t i = 0; i < a.brushes.size(); ++i) {
    const CmBrush &x = a.brushes[i], &y = b.brushes[i];
    if (!sameBits(x.bounds, y.bounds) || x.contents != y.contents || x.material != y.material ||
        x.primitiveNum != y.primitiveNum || x.firstPlane != y.firstPlane || x.numPlanes != y.numPlanes)
      return "brush " + std::to_string(i);
  }
  if (a.nodes.size() != b.nodes.size()) return "node count";
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    const CmNode &x = a.nodes[i], &y = b.nodes[i];
    if (x.planeType != y.planeType || !sameBits(x.planeDist, y.planeDist) || x.children[0] != y.children[0] ||
        x.children[1] != y.children[1] || x.parent != y.parent || x.firstPolygonRef != y.firstPolygonRef ||
        x.numPolygonRefs != y.numPolygonRefs || x.firstBrushRef != y.firstBrushRef ||
        x.numBrushRefs != y.numBrushRefs)
      return "node " + std::to_string(i);
  }
  if (a.polygonRefs != b.polygonRefs) return "polygon refs";
  if (a.brushRefs != b.brushRefs) return "brush refs";
  if (a.stats.sharpEdges != b.stats.sharpEdges || a.stats.internalEdges != b.stats.internalEdges)
    return "stats";
  return {};
}

/// modelDifference of two sealed models.
inline std::string modelDifference(const CollisionModel& a, const CollisionModel& b) {
  return modelDifference(a.arrays(), b.arrays());
}

/// The text without the numbers of the memory-size hints.
inline std::string withoutMemoryHints(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  std::size_t pos = 0;
  for (;;) {
    std::size_t hint = text.find("Memory = */ ", pos);
    if (hint == std::string::npos) break;
    hint += 12;
    out.append(text, pos, hint - pos);
    while (hint < text.size() && text[hint] >= '0' && text[hint] <= '9') ++hint;
    pos = hint;
  }
  out.append(text, pos);
  return out;
}

}  // namespace cmkit::test
