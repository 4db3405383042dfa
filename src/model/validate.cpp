// Model invariants: see validate.h.
#include "cmkit/validate.h"

#include <cmath>
#include <limits>

#include "geometry/winding.h"

namespace cmkit {

std::string Violation::toString() const {
  std::string s = "model \"" + model + "\" " + itemKind;
  if (item >= 0) s += " " + std::to_string(item);
  return s + ": " + message;
}

namespace {

class Validator {
 public:
  Validator(const ModelArrays& m, std::size_t maxViolations, bool structureOnly)
      : m_(m), max_(maxViolations), structureOnly_(structureOnly) {}

  std::vector<Violation> run() {
    vertices();
    edges();
    polygons();
    brushes();
    tree();
    return std::move(out_);
  }

 private:
  void report(const char* kind, std::int64_t item, std::string message,
              Violation::Kind violation = Violation::Kind::Structure) {
    if (structureOnly_ && violation == Violation::Kind::Geometry) return;
    if (out_.size() < max_) out_.push_back({m_.name, kind, item, std::move(message), violation});
  }
  /// An odd shape rather than corrupt data (see Violation::Kind).
  void reportGeometry(const char* kind, std::int64_t item, std::string message) {
    report(kind, item, std::move(message), Violation::Kind::Geometry);
  }
  static std::string str(Real v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", double(v));
    return buf;
  }
  static bool unitLength(const Vec3& n) {
    return std::fabs(n.lengthSquared() - 1) <= tol::kValidateUnitEpsilon;
  }
  bool edgeInRange(std::int32_t e) const {
    const std::int64_t a = e < 0 ? -std::int64_t(e) : e;
    return a > 0 && a < std::int64_t(m_.edges.size());
  }
  bool vertexInRange(std::int32_t v) const { return v >= 0 && std::size_t(v) < m_.vertices.size(); }

  void vertices() {
    for (std::size_t i = 0; i < m_.vertices.size(); ++i)
      if (!m_.vertices[i].isFinite()) reportGeometry("vertex", std::int64_t(i), "non-finite coordinate");
  }

  void edges() {
    // Uses per edge, split by direction.
    forward_.assign(m_.edges.size(), 0);
    backward_.assign(m_.edges.size(), 0);
    for (const CmPolygon& p : m_.polygons) {
      if (std::size_t(p.firstEdge) + p.numEdges > m_.polygonEdges.size())
        continue;  // reported with the polygon
      for (const std::int32_t e : m_.edgesOf(p)) {
        if (!edgeInRange(e)) continue;
        (e > 0 ? forward_ : backward_)[std::size_t(e > 0 ? e : -e)]++;
      }
    }
    for (std::size_t i = 1; i < m_.edges.size(); ++i) {
      const CmEdge& e = m_.edges[i];
      if (!vertexInRange(e.vertex[0]) || !vertexInRange(e.vertex[1])) {
        report("edge", std::int64_t(i),
               "vertex number out of range (" + std::to_string(e.vertex[0]) + ", " +
                   std::to_string(e.vertex[1]) + ")");
        continue;
      }
      if (e.vertex[0] == e.vertex[1])
        reportGeometry("edge", std::int64_t(i), "both ends are the same vertex");
      const int users = forward_[i] + backward_[i];
      if (users > 2)
        reportGeometry("edge", std::int64_t(i), "used by " + std::to_string(users) + " polygons");
      if (users == 2 && forward_[i] != 1)
        reportGeometry("edge", std::int64_t(i), "used twice in the same direction");
    }
  }

  void polygons() {
    for (std::size_t i = 0; i < m_.polygons.size(); ++i) {
      const CmPolygon& p = m_.polygons[i];
      const auto item = std::int64_t(i);
      if (std::size_t(p.firstEdge) + p.numEdges > m_.polygonEdges.size()) {
        report("polygon", item, "edge range beyond the edge list");
        continue;
      }
      if (p.numEdges < 3) reportGeometry("polygon", item, "fewer than 3 edges");
      bool edgesOk = true;
      bool repeated = false;  // reported once per polygon
      const auto list = m_.edgesOf(p);
      for (std::size_t k = 0; k < list.size(); ++k) {
        if (!edgeInRange(list[k])) {
          report("polygon", item, "edge number " + std::to_string(list[k]) + " out of range");
          edgesOk = false;
          continue;
        }
        for (std::size_t j = 0; j < k && !repeated; ++j) {
          if (list[j] == list[k] || list[j] == -list[k]) {
            reportGeometry("polygon", item, "uses edge " + std::to_string(std::abs(list[k])) + " twice");
            repeated = true;
          }
        }
      }
      if (p.material < -1 || (p.material >= 0 && std::size_t(p.material) >= m_.materials.size()))
        report("polygon", item, "material index out of range");
      if (!edgesOk) continue;
      bool verticesOk = true;
      for (const std::int32_t e : list) {
        const CmEdge& edge = m_.edges[std::size_t(e < 0 ? -e : e)];
        verticesOk &= vertexInRange(edge.vertex[0]) && vertexInRange(edge.vertex[1]);
      }
      if (!verticesOk) continue;  // reported with the edge
      // Continuity: each edge starts where the previous one ends.
      if (const std::ptrdiff_t k = m_.brokenEdgeLoopAt(p); k >= 0)
        report("polygon", item, "edge loop broken before edge " + std::to_string(list[std::size_t(k)]));
      if (!unitLength(p.plane.normal)) reportGeometry("polygon", item, "normal is not unit length");
      Real worst = 0;
      bool outside = false;
      const Bounds grown = p.bounds.expanded(tol::kValidateBoundsEpsilon);
      for (const std::int32_t e : list) {
        const Vec3& v = m_.vertices[std::size_t(m_.edgeStart(e))];
        worst = std::max(worst, std::fabs(p.plane.distance(v)));
        outside |= !grown.containsPoint(v);
      }
      if (worst > tol::kValidatePlanarEpsilon)
        reportGeometry("polygon", item, "not planar: a vertex is " + str(worst) + " off its plane");
      if (outside) reportGeometry("polygon", item, "a vertex lies outside the polygon's bounds");
    }
  }

  void brushes() {
    for (std::size_t i = 0; i < m_.brushes.size(); ++i) {
      const CmBrush& b = m_.brushes[i];
      const auto item = std::int64_t(i);
      if (std::size_t(b.firstPlane) + b.numPlanes > m_.brushPlanes.size()) {
        report("brush", item, "plane range beyond the plane list");
        continue;
      }
      const auto planes = m_.planesOf(b);
      bool unit = true;
      for (const Plane& pl : planes)
        unit &= unitLength(pl.normal) && pl.normal.isFinite() && std::isfinite(pl.dist);
      if (!unit) {
        reportGeometry("brush", item, "a plane normal is not unit length");
        continue;
      }
      // The corners of the volume: every plane's base winding clipped by all
      // the others (inward).
      bool any = false, huge = false, outside = false;
      const Bounds grown = b.bounds.expanded(tol::kValidateBoundsEpsilon);
      for (std::size_t k = 0; k < planes.size(); ++k) {
        detail::Winding w = detail::Winding::baseForPlane(planes[k].flipped());
        for (std::size_t j = 0; j < planes.size() && !w.empty(); ++j)
          if (j != k) w.clipInPlace(planes[j].flipped(), 0);
        if (w.empty()) continue;
        any = true;
        huge |= w.isHuge();
        for (const Vec3& p : w.points()) outside |= !grown.containsPoint(p);
      }
      if (!any) {
        reportGeometry("brush", item, "its planes enclose no volume");
      } else if (huge) {
        reportGeometry("brush", item, "its planes do not enclose a bounded volume");
      } else if (outside) {
        reportGeometry("brush", item, "a corner of the brush lies outside its bounds");
      }
      if (b.material < -1 || (b.material >= 0 && std::size_t(b.material) >= m_.materials.size()))
        report("brush", item, "material index out of range");
    }
  }

  // Node regions follow the splits from the model bounds.
  void tree() {
    if (m_.nodes.empty()) {
      if (!m_.polygons.empty() || !m_.brushes.empty()) report("model", -1, "no tree but items");
      return;
    }
    std::vector<char> polygonSeen(m_.polygons.size(), 0), brushSeen(m_.brushes.size(), 0);
    struct Visit {
      std::int32_t node;
      std::int32_t parent;
      Bounds region;
    };
    const Bounds all = m_.bounds.expanded(tol::kValidateBoundsEpsilon);
    std::vector<Visit> stack{{0, -1, all}};
    std::int32_t expected = 0;
    while (!stack.empty()) {
      const Visit v = stack.back();
      stack.pop_back();
      if (v.node != expected) {
        report("node", v.node,
               "not stored in pre-order (front child first): expected node " + std::to_string(expected));
        return;  // the rest would only repeat it
      }
      ++expected;
      const CmNode& n = m_.nodes[std::size_t(v.node)];
      if (n.parent != v.parent)
        report("node", v.node,
               "parent link " + std::to_string(n.parent) + ", should be " + std::to_string(v.parent));
      checkRefs(v.node, n, v.region, polygonSeen, brushSeen);
      if (n.isLeaf()) continue;
      if (n.planeType > 2) {
        report("node", v.node, "plane type " + std::to_string(n.planeType) + " out of range");
        return;
      }
      for (const std::int32_t c : n.children) {
        if (c <= v.node || std::size_t(c) >= m_.nodes.size()) {
          report("node", v.node, "child " + std::to_string(c) + " out of range");
          return;
        }
      }
      Bounds front = v.region, back = v.region;
      front.min[n.planeType] = std::max(front.min[n.planeType], n.planeDist);
      back.max[n.planeType] = std::min(back.max[n.planeType], n.planeDist);
      stack.push_back({n.children[1], v.node, back});
      stack.push_back({n.children[0], v.node, front});
    }
    if (std::size_t(expected) != m_.nodes.size())
      report("model", -1,
             std::to_string(m_.nodes.size() - std::size_t(expected)) + " nodes are not in the tree");
    for (std::size_t i = 0; i < polygonSeen.size(); ++i)
      if (!polygonSeen[i]) report("polygon", std::int64_t(i), "not referenced from the tree");
    for (std::size_t i = 0; i < brushSeen.size(); ++i)
      if (!brushSeen[i]) report("brush", std::int64_t(i), "not referenced from the tree");
  }

  void checkRefs(std::int32_t nodeNum, const CmNode& n, const Bounds& region, std::vector<char>& polygonSeen,
                 std::vector<char>& brushSeen) {
    const auto node = std::int64_t(nodeNum);
    if (std::size_t(n.firstPolygonRef) + n.numPolygonRefs > m_.polygonRefs.size() ||
        std::size_t(n.firstBrushRef) + n.numBrushRefs > m_.brushRefs.size()) {
      report("node", node, "reference range beyond the reference lists");
      return;
    }
    const Bounds modelBounds = m_.bounds.expanded(tol::kValidateBoundsEpsilon);
    for (const std::int32_t p : m_.polygonsAt(n)) {
      if (p < 0 || std::size_t(p) >= m_.polygons.size()) {
        report("node", node, "references polygon " + std::to_string(p) + ", out of range");
        continue;
      }
      const Bounds& b = m_.polygons[std::size_t(p)].bounds;
      if (!polygonSeen[std::size_t(p)] && !modelBounds.containsBounds(b))
        reportGeometry("polygon", p, "outside the model bounds");
      polygonSeen[std::size_t(p)] = 1;
      if (!region.expanded(tol::kValidateBoundsEpsilon).intersects(b))
        report("polygon", p,
               "referenced from node " + std::to_string(nodeNum) + " whose region it does not touch");
    }
    for (const std::int32_t bi : m_.brushesAt(n)) {
      if (bi < 0 || std::size_t(bi) >= m_.brushes.size()) {
        report("node", node, "references brush " + std::to_string(bi) + ", out of range");
        continue;
      }
      const Bounds& b = m_.brushes[std::size_t(bi)].bounds;
      if (b.isCleared()) {  // an empty brush (reported with the brush): it is anywhere and nowhere
        brushSeen[std::size_t(bi)] = 1;
        continue;
      }
      if (!brushSeen[std::size_t(bi)] && !modelBounds.containsBounds(b))
        reportGeometry("brush", bi, "outside the model bounds");
      brushSeen[std::size_t(bi)] = 1;
      if (!region.expanded(tol::kValidateBoundsEpsilon).intersects(b))
        report("brush", bi,
               "referenced from node " + std::to_string(nodeNum) + " whose region it does not touch");
    }
  }

  const ModelArrays& m_;
  std::size_t max_;
  bool structureOnly_;
  std::vector<Violation> out_;
  std::vector<int> forward_, backward_;
};

}  // namespace

std::vector<Violation> validateModel(const ModelArrays& arrays, std::size_t maxViolations) {
  return Validator(arrays, maxViolations, false).run();
}

std::vector<Violation> validateModel(const CollisionModel& model, std::size_t maxViolations) {
  return validateModel(model.arrays(), maxViolations);
}

std::vector<Violation> structureViolations(const ModelArrays& arrays, std::size_t maxViolations) {
  return Validator(arrays, maxViolations, true).run();
}

}  // namespace cmkit
