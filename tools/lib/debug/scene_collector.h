// A DebugDraw that collects drawn primitives into groups (meshes) for the
// glTF and OBJ writers: one group per (model, kind, contents or trace).
#pragma once

#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "cmkit/tools/debug_draw.h"
#include "cmkit/tools/export.h"

namespace cmkit::detail {

/// The coarse kind of a group, as the exporters name it.
enum class GroupKind : std::uint8_t { Polygons, Edges, InternalEdges, Normals, Trace };

/// Name used in node extras: "polygons", "edges", "internal edges", ...
const char* toString(GroupKind kind);

/// Primitives of one mesh.
struct Group {
  GroupKind kind = GroupKind::Polygons;
  std::string model;                      ///< model name (empty for traces)
  std::int32_t modelIndex = -1;           ///< index of the model (-1 for traces)
  std::uint32_t contents = 0;             ///< polygons and edges
  std::int32_t trace = -1;                ///< trace index (Trace groups)
  DrawKind drawKind = DrawKind::Polygon;  ///< for trace groups: path, shape, contact...
  Rgba color;
  bool triangles = false;  ///< triangles (with normals) or lines
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;  ///< one per position for triangles
  std::vector<std::uint32_t> indices;
};

/// Collects primitives. Set `model` before drawing each model.
class SceneCollector final : public DebugDraw {
 public:
  void line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag& tag) override;
  void polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
               const DrawTag& tag) override;
  void text(const Vec3&, std::string_view, const Rgba&, const DrawTag&) override {}

  /// Name of the model being drawn.
  std::string model;
  /// Index of the model being drawn (groups are per model).
  std::int32_t modelIndex = -1;
  /// The groups in creation order (deterministic).
  std::vector<Group>& groups() { return groups_; }

 private:
  Group& groupFor(const DrawTag& tag, const Rgba& color, bool triangles);
  std::vector<Group> groups_;
  /// (model index, kind, contents, trace, draw kind) -> index into groups_.
  std::map<std::tuple<std::int32_t, int, std::uint32_t, std::int32_t, int>, std::size_t> index_;
};

/// Draws the models and traces into groups, as every exporter needs them.
std::vector<Group> collectScene(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                                const ExportOptions& options);

}  // namespace cmkit::detail
