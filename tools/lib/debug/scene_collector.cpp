// Collecting drawn primitives into exporter groups.
#include "debug/scene_collector.h"

namespace cmkit::detail {
namespace {

/// Colour of exported edges (dark, to show on the coloured polygons).
constexpr Rgba kEdgeColor{24, 24, 28, 255};

/// A named function, not a lambda: Clang 14 writes a lambda's source path into
/// the debug information unmapped by -ffile-prefix-map (installed_tree).
bool isEdgeGroup(const Group& g) { return g.kind == GroupKind::Edges; }

GroupKind groupKindOf(DrawKind kind) {
  switch (kind) {
    case DrawKind::Polygon:
      return GroupKind::Polygons;
    case DrawKind::Edge:
    case DrawKind::SharedEdge:
      return GroupKind::Edges;
    case DrawKind::InternalEdge:
      return GroupKind::InternalEdges;
    case DrawKind::EdgeNormal:
    case DrawKind::PolygonNormal:
      return GroupKind::Normals;
    default:
      return GroupKind::Trace;
  }
}

}  // namespace

const char* toString(GroupKind kind) {
  switch (kind) {
    case GroupKind::Polygons:
      return "polygons";
    case GroupKind::Edges:
      return "edges";
    case GroupKind::InternalEdges:
      return "internal edges";
    case GroupKind::Normals:
      return "normals";
    case GroupKind::Trace:
      return "trace";
  }
  return "?";
}

Group& SceneCollector::groupFor(const DrawTag& tag, const Rgba& color, bool triangles) {
  const GroupKind kind = groupKindOf(tag.kind);
  const bool isTrace = kind == GroupKind::Trace;
  // Polygons are grouped by contents; edges per model; trace parts per trace
  // and part.
  const std::uint32_t contents = kind == GroupKind::Polygons ? tag.contents : 0;
  const std::int32_t trace = isTrace ? tag.feature : -1;
  const int drawKind = isTrace ? int(tag.kind) : -1;
  const auto key = std::make_tuple(isTrace ? -1 : modelIndex, int(kind), contents, trace, drawKind);
  const auto [it, inserted] = index_.try_emplace(key, groups_.size());
  if (inserted) {
    Group& g = groups_.emplace_back();
    g.kind = kind;
    g.model = isTrace ? std::string() : model;
    g.modelIndex = isTrace ? -1 : modelIndex;
    g.contents = isTrace ? tag.contents : contents;
    g.trace = trace;
    g.drawKind = tag.kind;
    g.color = kind == GroupKind::Edges ? kEdgeColor : color;
    g.triangles = triangles;
  }
  return groups_[it->second];
}

void SceneCollector::line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag& tag) {
  Group& g = groupFor(tag, color, false);
  const auto base = std::uint32_t(g.positions.size());
  g.positions.push_back(a);
  g.positions.push_back(b);
  g.indices.push_back(base);
  g.indices.push_back(base + 1);
}

void SceneCollector::polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
                             const DrawTag& tag) {
  if (points.size() < 3) return;
  Group& g = groupFor(tag, color, true);
  const auto base = std::uint32_t(g.positions.size());
  for (const Vec3& p : points) {
    g.positions.push_back(p);
    g.normals.push_back(normal);
  }
  for (std::uint32_t i = 1; i + 1 < std::uint32_t(points.size()); ++i) {
    g.indices.push_back(base);
    g.indices.push_back(base + i);
    g.indices.push_back(base + i + 1);
  }
}

std::vector<Group> collectScene(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                                const ExportOptions& options) {
  SceneCollector collector;
  for (std::size_t i = 0; i < models.size(); ++i) {
    const ModelPtr& m = models[i];
    if (!m) continue;
    const Placement place = i < options.placements.size() ? options.placements[i] : Placement{};
    collector.model = m->name();
    collector.modelIndex = std::int32_t(i);
    DrawOptions draw;
    draw.contentMask = options.contentMask;
    draw.filled = true;
    drawModel(collector, *m, place, draw);
    if (options.edges || options.internalEdges) {
      // Edges and internal edges come from one walk; drop what is not wanted.
      draw.filled = false;
      draw.internalEdges = options.internalEdges;
      drawModel(collector, *m, place, draw);
    }
  }
  drawTraceRecords(collector, traces);
  std::vector<Group> groups = std::move(collector.groups());
  if (!options.edges) std::erase_if(groups, isEdgeGroup);
  return groups;
}

}  // namespace cmkit::detail
