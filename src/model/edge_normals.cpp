// Edge normals (docs/algorithms.md): see edge_normals.h for the order and the
// formulas.
#include "model/edge_normals.h"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace cmkit::detail {

namespace {

// One face's contribution to an edge normal, the original's rule: n is the
// face's normal, t the edge direction as the face walks it, `alone` whether
// the face is the edge's only user.
void addFaceToEdgeNormal(Vec3& normal, const Vec3& n, const Vec3& t, bool alone, int& sharpEdges) {
  // The original computes the sharp-edge scale in float: 0.5 / (0.5 + 0.5 * -0.7).
  const Real sharpScale = Real(0.5) / (Real(0.5) + Real(0.5) * tol::kSharpEdgeDot);
  if (normal.isZero()) {
    if (alone) {
      normal = t.cross(n);  // outward in the polygon's plane
      normal.normalize();
    } else {
      normal = n;
    }
    return;
  }
  const Real dot = normal.dot(n);
  if (dot < tol::kSharpEdgeDot) {
    // The faces fold back on each other: the longest normal that still
    // points out of both (the bisector would be nearly zero).
    Vec3 folded = normal.cross(t) + n.cross(-t);
    const Real length = folded.length();
    folded *= safeDivide(sharpScale, length);
    normal = folded;
    ++sharpEdges;
  } else {
    const Real s = Real(0.5) / (Real(0.5) + Real(0.5) * dot);
    normal = (normal + n) * s;
  }
}

// A polygon's use of an edge: the edge number and whether the polygon walks
// it from vertex[0] to vertex[1]. Null when the edge or its vertices are out
// of range (validated models never have these).
const CmEdge* usedEdge(const ModelArrays& model, std::int32_t signedEdge, std::size_t& e) {
  e = std::size_t(signedEdge < 0 ? -signedEdge : signedEdge);
  if (e == 0 || e >= model.edges.size()) return nullptr;
  const CmEdge& edge = model.edges[e];
  const std::size_t nv = model.vertices.size();
  if (std::size_t(edge.vertex[0]) >= nv || std::size_t(edge.vertex[1]) >= nv) return nullptr;
  return &edge;
}

// t: the edge direction as a polygon walking it as signedEdge does.
Vec3 walkDirection(const ModelArrays& model, const CmEdge& edge, std::int32_t signedEdge) {
  const Vec3& a = model.vertices[std::size_t(edge.vertex[0])];
  const Vec3& b = model.vertices[std::size_t(edge.vertex[1])];
  return signedEdge > 0 ? b - a : a - b;
}

// Every polygon referenced from the tree, once, in the original's order
// (edge_normals.h).
std::vector<std::uint32_t> polygonsInTreeOrder(const ModelArrays& model) {
  std::vector<std::uint32_t> order;
  if (model.nodes.empty()) return order;
  order.reserve(model.polygons.size());
  // What the walk reads of a node, copied in one pass in the nodes' order:
  // they are stored front child first, and the walk, back child first,
  // jumps across the array at every step; a third of the bytes keeps more
  // of them in the cache.
  struct Step {
    std::int32_t children[2];
    std::uint32_t firstRef, numRefs;
  };
  std::vector<Step> steps(model.nodes.size());
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    const CmNode& node = model.nodes[n];
    steps[n] = {{node.isLeaf() ? -1 : node.children[0], node.isLeaf() ? -1 : node.children[1]},
                node.firstPolygonRef,
                node.numPolygonRefs};
  }
  std::vector<char> visited(model.polygons.size(), 0);
  // Pre-order walk: node list, back subtree, front subtree. The stack holds
  // nodes still to visit; pushing front before back pops back first.
  std::vector<std::int32_t> stack{0};
  std::vector<char> nodeSeen(model.nodes.size(), 0);  // guards against malformed child links
  while (!stack.empty()) {
    const std::int32_t nodeNum = stack.back();
    stack.pop_back();
    if (nodeNum < 0 || std::size_t(nodeNum) >= model.nodes.size() || nodeSeen[std::size_t(nodeNum)]) continue;
    nodeSeen[std::size_t(nodeNum)] = 1;
    const Step& step = steps[std::size_t(nodeNum)];
    for (std::uint32_t r = 0; r < step.numRefs; ++r) {
      const std::int32_t p = model.polygonRefs[std::size_t(step.firstRef) + r];
      if (p < 0 || std::size_t(p) >= model.polygons.size() || visited[std::size_t(p)]) continue;
      visited[std::size_t(p)] = 1;
      order.push_back(std::uint32_t(p));
    }
    if (step.children[0] < 0) continue;  // a leaf
    stack.push_back(step.children[0]);   // front: visited after the whole back subtree
    stack.push_back(step.children[1]);   // back: next
  }
  return order;
}

// Calls visit(polygon index) for every polygon referenced from the tree, once,
// in the original's order (edge_normals.h). In that order the polygons, and
// more so their edges, lie all over the model's arrays: a polygon's record is
// fetched 2 * kFetchAhead polygons ahead, its edge list (found in the record,
// by then at hand) kFetchAhead ahead, its edges half as far ahead (from the
// list fetched before), so that a few wait for memory at once instead of one
// at a time. (Reading the record for its list's place in the same step as
// fetching it waited for memory every time.)
template <class Visit>
void visitPolygonsInTreeOrder(const ModelArrays& model, Visit&& visit) {
  constexpr std::size_t kFetchAhead = 16;
  const std::vector<std::uint32_t> order = polygonsInTreeOrder(model);
  for (std::size_t i = 0; i < order.size(); ++i) {
    if (i + 2 * kFetchAhead < order.size()) __builtin_prefetch(&model.polygons[order[i + 2 * kFetchAhead]]);
    if (i + kFetchAhead < order.size())
      __builtin_prefetch(model.polygonEdges.data() + model.polygons[order[i + kFetchAhead]].firstEdge);
    if (i + kFetchAhead / 2 < order.size()) {
      for (const std::int32_t e : model.edgesOf(model.polygons[order[i + kFetchAhead / 2]])) {
        const auto edge = std::size_t(e < 0 ? -std::int64_t(e) : e);
        if (edge < model.edges.size()) __builtin_prefetch(&model.edges[edge]);
      }
    }
    visit(std::size_t(order[i]));
  }
}

int originalEdgeNormals(ModelArrays& model) {
  int sharpEdges = 0;
  visitPolygonsInTreeOrder(model, [&](std::size_t p) {
    const CmPolygon& polygon = model.polygons[p];
    for (const std::int32_t signedEdge : model.edgesOf(polygon)) {
      std::size_t e = 0;
      if (!usedEdge(model, signedEdge, e)) continue;
      CmEdge& edge = model.edges[e];
      addFaceToEdgeNormal(edge.normal, polygon.plane.normal, walkDirection(model, edge, signedEdge),
                          edge.numUsers == 1, sharpEdges);
    }
  });
  return sharpEdges;
}

// ---- two-sided sheets (EdgeNormalRule::TwoSidedSheets) ----------------------

// One polygon's use of an edge, in visiting order.
struct EdgeUse {
  std::size_t polygon = 0;
  std::int32_t signedEdge = 0;
  bool forward = false;  ///< walks the line from its lower to its higher vertex number
  int twin = -1;         ///< index (in the line's uses) of its reversed twin, -1 for none
};

// The uses of one line (every edge between the same two vertices: the
// builder gives a third polygon at a line an edge of its own, so a two-sided
// polygon's neighbour uses another edge there than its reversed copy does).
struct LineUses {
  std::vector<std::size_t> edges;  ///< its edge numbers, in first-use order
  std::vector<EdgeUse> uses;
};

// Pairs each use with an earlier unpaired one it is the reversed twin of: the
// other face of the same sheet (normals opposite within
// kRobustEdgeParallelDot, the line walked the other way, the same material
// and contents, as a two-sided polygon's reversed copy has). Two brushes
// back to back with different contents (a clip brush against a solid one,
// both faces kept) are not a sheet: they keep the original's normal, which
// points out of the pair's solid side (test_robust_edges_misses.cpp).
// Returns the number of pairs.
int pairTwins(const ModelArrays& model, std::vector<EdgeUse>& uses) {
  int pairs = 0;
  for (std::size_t j = 0; j < uses.size(); ++j) {
    const CmPolygon& pj = model.polygons[uses[j].polygon];
    for (std::size_t i = 0; i < j; ++i) {
      if (uses[i].twin >= 0 || uses[i].forward == uses[j].forward) continue;
      const CmPolygon& pi = model.polygons[uses[i].polygon];
      if (pi.material != pj.material || pi.contents != pj.contents) continue;
      if (pi.plane.normal.dot(pj.plane.normal) >= -tol::kRobustEdgeParallelDot) continue;
      uses[i].twin = int(j);
      uses[j].twin = int(i);
      ++pairs;
      break;
    }
  }
  return pairs;
}

// Which uses of a line with twins give its normal (edge_normals.h).
std::vector<char> sheetContributors(const ModelArrays& model, const LineUses& line, int pairs) {
  const std::vector<EdgeUse>& uses = line.uses;
  std::vector<char> take(uses.size(), 0);
  const auto normalOf = [&](std::size_t u) -> const Vec3& {
    return model.polygons[uses[u].polygon].plane.normal;
  };
  bool unpaired = false;
  for (const EdgeUse& u : uses) unpaired |= u.twin < 0;
  if (!unpaired && pairs == 1) {
    take[0] = 1;  // a sheet's boundary: its one face
    return take;
  }
  if (!unpaired && pairs == 2) {
    // Two sheets meet (or one sheet folds): of each pair, the faces that walk
    // the line opposite ways (one consistently oriented surface), on the side
    // where that surface is convex (flat: the first face's side).
    std::size_t a = 0, b = 0;
    for (std::size_t u = 1; u < uses.size(); ++u) {
      if (int(u) != uses[a].twin && uses[u].forward != uses[a].forward) {
        b = u;
        break;
      }
    }
    // s: the outward in-plane direction of b at the line, pointing across it
    // towards a's face. a's face bends away from b's front (a convex fold
    // seen from that front) when a's normal leans along s.
    const Vec3 s =
        walkDirection(model, model.edges[std::size_t(std::abs(uses[b].signedEdge))], uses[b].signedEdge)
            .cross(normalOf(b));
    if (normalOf(a).dot(s) < 0) {
      a = std::size_t(uses[a].twin);
      b = std::size_t(uses[b].twin);
    }
    take[a] = take[b] = 1;
    return take;
  }
  // Anything else (three or more sheets at a line, a sheet meeting one-sided
  // faces): every unpaired face, and of each pair the face whose normal is
  // nearer the first unpaired face's (else the first face's).
  std::size_t reference = 0;
  for (std::size_t u = 0; u < uses.size(); ++u) {
    if (uses[u].twin < 0) {
      reference = u;
      break;
    }
  }
  const Vec3& ref = normalOf(reference);
  for (std::size_t u = 0; u < uses.size(); ++u) {
    const int t = uses[u].twin;
    if (t < 0) {
      take[u] = 1;
    } else if (std::size_t(t) > u) {  // decide each pair at its first face
      const bool first = normalOf(u).dot(ref) >= normalOf(std::size_t(t)).dot(ref);
      take[first ? u : std::size_t(t)] = 1;
    }
  }
  return take;
}

int sheetAwareEdgeNormals(ModelArrays& model) {
  // The uses of every line, in the original's visiting order.
  std::vector<LineUses> lines;
  std::unordered_map<std::uint64_t, std::size_t> lineOf;
  visitPolygonsInTreeOrder(model, [&](std::size_t p) {
    for (const std::int32_t signedEdge : model.edgesOf(model.polygons[p])) {
      std::size_t e = 0;
      const CmEdge* edge = usedEdge(model, signedEdge, e);
      if (!edge) continue;
      const auto v0 = std::uint32_t(edge->vertex[0]), v1 = std::uint32_t(edge->vertex[1]);
      const std::uint64_t key = (std::uint64_t(std::min(v0, v1)) << 32) | std::max(v0, v1);
      const auto [it, added] = lineOf.try_emplace(key, lines.size());
      if (added) lines.emplace_back();
      LineUses& line = lines[it->second];
      if (std::find(line.edges.begin(), line.edges.end(), e) == line.edges.end()) line.edges.push_back(e);
      const bool walksV0ToV1 = signedEdge > 0;
      line.uses.push_back({p, signedEdge, walksV0ToV1 == (v0 < v1), -1});
    }
  });
  int sharpEdges = 0;
  for (LineUses& line : lines) {
    const int pairs = pairTwins(model, line.uses);
    if (pairs == 0) {
      // No two-sided sheet here: every edge as the original makes it.
      for (const EdgeUse& u : line.uses) {
        CmEdge& edge = model.edges[std::size_t(std::abs(u.signedEdge))];
        addFaceToEdgeNormal(edge.normal, model.polygons[u.polygon].plane.normal,
                            walkDirection(model, edge, u.signedEdge), edge.numUsers == 1, sharpEdges);
      }
      continue;
    }
    const std::vector<char> take = sheetContributors(model, line, pairs);
    const auto count = std::count(take.begin(), take.end(), char(1));
    Vec3 normal;
    for (std::size_t u = 0; u < line.uses.size(); ++u) {
      if (!take[u]) continue;
      const EdgeUse& use = line.uses[u];
      const CmEdge& edge = model.edges[std::size_t(std::abs(use.signedEdge))];
      addFaceToEdgeNormal(normal, model.polygons[use.polygon].plane.normal,
                          walkDirection(model, edge, use.signedEdge), count == 1, sharpEdges);
    }
    for (const std::size_t e : line.edges) model.edges[e].normal = normal;
  }
  return sharpEdges;
}

}  // namespace

int computeEdgeNormals(ModelArrays& model, EdgeNormalRule rule) {
  for (CmEdge& edge : model.edges) edge.normal = Vec3{};
  return rule == EdgeNormalRule::Original ? originalEdgeNormals(model) : sheetAwareEdgeNormals(model);
}

void computeModelBoundsAndContents(ModelArrays& model) {
  Bounds bounds;
  std::uint32_t contents = 0;
  for (const CmPolygon& p : model.polygons) {
    bounds.addPoint(p.bounds.min);
    bounds.addPoint(p.bounds.max);
    contents |= p.contents;
  }
  for (const CmBrush& b : model.brushes) {
    bounds.addPoint(b.bounds.min);
    bounds.addPoint(b.bounds.max);
    contents |= b.contents;
  }
  if (bounds.isCleared()) bounds = Bounds(Vec3{}, Vec3{});
  model.bounds = bounds;
  model.contents = contents;
}

}  // namespace cmkit::detail
