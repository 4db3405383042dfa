// Debug drawing of collision models and traces (the original's DrawModel,
// DrawNodePolygons, DrawPolygon, DrawEdge) through the DebugDraw interface.
#include <array>
#include <vector>

#include "cmkit/tools/debug_draw.h"

namespace cmkit {
namespace {

constexpr std::array<ContentStyle, 16> kStyles{{
    {"solid", contents::kSolid, {178, 170, 156, 255}},
    {"opaque", contents::kOpaque, {140, 140, 150, 255}},
    {"water", contents::kWater, {60, 120, 230, 160}},
    {"playerclip", contents::kPlayerClip, {220, 60, 200, 255}},
    {"monsterclip", contents::kMonsterClip, {230, 120, 40, 255}},
    {"moveableclip", contents::kMoveableClip, {200, 200, 60, 255}},
    {"ikclip", contents::kIkClip, {60, 200, 200, 255}},
    {"blood", contents::kBlood, {180, 20, 20, 255}},
    {"body", contents::kBody, {240, 190, 150, 255}},
    {"projectile", contents::kProjectile, {250, 250, 120, 255}},
    {"corpse", contents::kCorpse, {120, 90, 60, 255}},
    {"renderModel", contents::kRenderModel, {90, 200, 110, 255}},
    {"trigger", contents::kTrigger, {250, 160, 40, 128}},
    {"aas_solid", contents::kAasSolid, {100, 160, 100, 255}},
    {"aas_obstacle", contents::kAasObstacle, {160, 100, 100, 255}},
    {"flashlight_trigger", contents::kFlashlightTrigger, {250, 250, 250, 128}},
}};

/// Colour of polygons with no named flag set.
constexpr Rgba kNoContentsColor{200, 150, 160, 255};
/// Internal edges (the original draws them green).
constexpr Rgba kInternalEdgeColor = colors::kGreen;
/// Edges with more than two users (the original draws them blue).
constexpr Rgba kSharedEdgeColor = colors::kBlue;
/// Half the size of the cross that marks a point trace and a contact point.
constexpr Real kMarkerSize = 4;
/// Colours of trace primitives.
constexpr Rgba kPathColor = colors::kYellow;
constexpr Rgba kPathAfterStopColor{128, 128, 64, 255};
constexpr Rgba kStartTrmColor{150, 150, 150, 255};
constexpr Rgba kEndTrmColor = colors::kWhite;
constexpr Rgba kContactColor = colors::kRed;
constexpr Rgba kContactNormalColor = colors::kOrange;
/// Length of the drawn contact normal (map units).
constexpr Real kContactNormalLength = 16;

Vec3 toWorld(const Vec3& local, const Placement& p) { return local * p.axis + p.origin; }

// The state of one drawModel walk: visited marks for polygons and edges
// (the original's checkCount), owned by the call.
class ModelWalk {
 public:
  ModelWalk(DebugDraw& draw, const CollisionModel& model, const Placement& placement, const DrawOptions& o)
      : draw_(draw),
        model_(model),
        placement_(placement),
        options_(o),
        viewLocal_(placement.axis * (o.viewOrigin - placement.origin)),
        polygonDone_(model.polygons().size(), false),
        edgeDone_(model.edges().size(), false) {}

  void run() {
    if (model_.nodes().empty()) {
      for (std::size_t i = 0; i < model_.polygons().size(); ++i) visitPolygon(std::int32_t(i));
      return;
    }
    // Walk the tree from the root, both children unless the radius sphere's
    // box lies wholly on one side of the split.
    std::vector<std::int32_t> stack{0};
    while (!stack.empty()) {
      const CmNode& node = model_.nodes()[std::size_t(stack.back())];
      stack.pop_back();
      for (std::int32_t p : model_.polygonsAt(node)) visitPolygon(p);
      if (node.isLeaf()) continue;
      const Real v = viewLocal_[node.planeType];
      const bool useRadius = options_.radius > 0;
      if (useRadius && v > node.planeDist + options_.radius) {
        stack.push_back(node.children[0]);
      } else if (useRadius && v < node.planeDist - options_.radius) {
        stack.push_back(node.children[1]);
      } else {
        stack.push_back(node.children[1]);
        stack.push_back(node.children[0]);
      }
    }
  }

 private:
  bool outsideRadius(const CmPolygon& p) const {
    if (options_.radius <= 0) return false;
    for (int i = 0; i < 3; ++i) {
      if (p.bounds.min[i] > viewLocal_[i] + options_.radius) return true;
      if (p.bounds.max[i] < viewLocal_[i] - options_.radius) return true;
    }
    return false;
  }

  void visitPolygon(std::int32_t index) {
    if (polygonDone_[std::size_t(index)]) return;
    const CmPolygon& p = model_.polygons()[std::size_t(index)];
    if (outsideRadius(p)) return;
    polygonDone_[std::size_t(index)] = true;
    if ((p.contents & options_.contentMask) == 0) return;
    if (options_.backFaceCull && p.plane.distance(viewLocal_) < 0) return;
    drawPolygon(index, p);
  }

  Rgba polygonColor(const CmPolygon& p) const {
    return options_.colorByContents ? contentColor(p.contents) : options_.color;
  }

  void drawPolygon(std::int32_t index, const CmPolygon& p) {
    const auto edges = model_.edgesOf(p);
    if (options_.normals) {
      Vec3 center;
      for (std::int32_t e : edges) center += model_.vertices()[std::size_t(model_.edgeStart(e))];
      center *= Real(1) / Real(edges.size());
      const Vec3 c = toWorld(center, placement_);
      draw_.line(c, c + (p.plane.normal * placement_.axis) * kDrawNormalLength, colors::kMagenta,
                 {DrawKind::PolygonNormal, p.contents, index});
    }
    if (options_.filled) {
      points_.clear();
      for (std::int32_t e : edges)
        points_.push_back(toWorld(model_.vertices()[std::size_t(model_.edgeStart(e))], placement_));
      draw_.polygon(points_, p.plane.normal * placement_.axis, polygonColor(p),
                    {DrawKind::Polygon, p.contents, index});
      return;
    }
    for (std::int32_t e : edges) {
      const auto edgeNum = std::size_t(e < 0 ? -e : e);
      if (edgeDone_[edgeNum]) continue;
      edgeDone_[edgeNum] = true;
      drawEdge(e, p);
    }
  }

  void drawEdge(std::int32_t signedEdge, const CmPolygon& p) {
    const auto edgeNum = std::int32_t(signedEdge < 0 ? -signedEdge : signedEdge);
    const CmEdge& edge = model_.edges()[std::size_t(edgeNum)];
    const int side = signedEdge < 0 ? 1 : 0;
    const Vec3 a = toWorld(model_.vertices()[std::size_t(edge.vertex[side])], placement_);
    const Vec3 b = toWorld(model_.vertices()[std::size_t(edge.vertex[1 - side])], placement_);
    if (edge.internal) {
      if (options_.internalEdges)
        draw_.line(a, b, kInternalEdgeColor, {DrawKind::InternalEdge, p.contents, edgeNum});
    } else if (edge.numUsers > 2) {
      draw_.line(a, b, kSharedEdgeColor, {DrawKind::SharedEdge, p.contents, edgeNum});
    } else {
      draw_.line(a, b, polygonColor(p), {DrawKind::Edge, p.contents, edgeNum});
    }
    if (options_.normals) {
      const Vec3 mid = (a + b) * Real(0.5);
      draw_.line(mid, mid + (edge.normal * placement_.axis) * kDrawNormalLength, colors::kCyan,
                 {DrawKind::EdgeNormal, p.contents, edgeNum});
    }
  }

  DebugDraw& draw_;
  const CollisionModel& model_;
  const Placement& placement_;
  const DrawOptions& options_;
  Vec3 viewLocal_;  ///< the view origin in the model's frame
  std::vector<bool> polygonDone_;
  std::vector<bool> edgeDone_;
  std::vector<Vec3> points_;  ///< scratch winding
};

void drawCross(DebugDraw& draw, const Vec3& at, Real size, const Rgba& color, const DrawTag& tag) {
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 d;
    d[axis] = size;
    draw.line(at - d, at + d, color, tag);
  }
}

}  // namespace

std::string_view toString(DrawKind kind) {
  switch (kind) {
    case DrawKind::Polygon:
      return "polygon";
    case DrawKind::Edge:
      return "edge";
    case DrawKind::SharedEdge:
      return "shared edge";
    case DrawKind::InternalEdge:
      return "internal edge";
    case DrawKind::EdgeNormal:
      return "edge normal";
    case DrawKind::PolygonNormal:
      return "polygon normal";
    case DrawKind::TracePath:
      return "trace path";
    case DrawKind::TraceModel:
      return "trace model";
    case DrawKind::Contact:
      return "contact";
    case DrawKind::ContactNormal:
      return "contact normal";
    case DrawKind::Label:
      return "label";
  }
  return "?";
}

std::span<const ContentStyle> contentStyles() { return kStyles; }

Rgba contentColor(std::uint32_t contents) {
  for (const ContentStyle& s : kStyles)
    if (contents & s.flag) return s.color;
  return kNoContentsColor;
}

void drawModel(DebugDraw& draw, const CollisionModel& model, const Placement& placement,
               const DrawOptions& options) {
  ModelWalk(draw, model, placement, options).run();
}

void drawTraceModel(DebugDraw& draw, const TraceModel* trm, const Vec3& origin, const Mat3& axis,
                    const Rgba& color, const DrawTag& tag) {
  if (trm == nullptr || trm->isPoint() || trm->numEdges() == 0) {
    drawCross(draw, origin, kMarkerSize, color, tag);
    return;
  }
  for (int e = 1; e <= trm->numEdges(); ++e) {
    const TrmEdge& edge = trm->edge(e);
    draw.line(trm->vertex(edge.v[0]) * axis + origin, trm->vertex(edge.v[1]) * axis + origin, color, tag);
  }
}

void drawTrace(DebugDraw& draw, const TraceDrawing& t) {
  const DrawTag path{DrawKind::TracePath, 0, t.index};
  const DrawTag shape{DrawKind::TraceModel, 0, t.index};
  const Vec3 stop = t.result.endPos;
  if (t.start != t.end) {
    draw.line(t.start, stop, kPathColor, path);
    if (t.result.fraction < 1) draw.line(stop, t.end, kPathAfterStopColor, path);
    drawTraceModel(draw, t.trm, t.start, t.trmAxis, kStartTrmColor, shape);
  }
  drawTraceModel(draw, t.trm, stop, t.result.endAxis, kEndTrmColor, shape);
  const ContactInfo& c = t.result.contact;
  if (c.type == ContactType::None) return;
  drawCross(draw, c.point, kMarkerSize, kContactColor, {DrawKind::Contact, c.contents, t.index});
  draw.line(c.point, c.point + c.normal * kContactNormalLength, kContactNormalColor,
            {DrawKind::ContactNormal, c.contents, t.index});
}

void drawTraceRecords(DebugDraw& draw, std::span<const TraceRecord> records) {
  for (std::size_t i = 0; i < records.size(); ++i) {
    const TraceRecord& r = records[i];
    if (r.op.empty() || r.op == "pointcontents" || !r.error.empty()) continue;
    TraceDrawing t;
    t.trm = r.trm ? &*r.trm : nullptr;
    t.trmAxis = r.trmAxis;
    t.start = r.start;
    t.end = r.end;
    t.result = r.result;
    t.index = std::int32_t(i);
    drawTrace(draw, t);
  }
}

}  // namespace cmkit
