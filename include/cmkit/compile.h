// compile.h: building collision models from a parsed map (the original's
// map -> collision model pipeline).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/proc_file.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// The most sides a brush may have. Building a brush clips each side's plane
/// by every other side (sides^2 clips: 2000 sides take about a second, 20 000
/// took 53 s with no progress), so a larger brush is refused with an Error
/// naming its line. Real brushes have a few dozen sides.
inline constexpr std::size_t kMaxBrushSides = 4096;

/// Options of the map -> model build.
struct BuildOptions {
  /// Called with (entities done, entities in all) as the build progresses;
  /// may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
  /// The renderer's BSP of the map's .proc file (loadProcFileForMap), or
  /// null. When set and usable, the world model (the first model built)
  /// drops every solid polygon winding lying entirely in its opaque solid
  /// leaves, as the original does (docs/algorithms.md); the count
  /// is ModelStats::procPolygonsRemoved. Must outlive the call.
  const ProcBsp* procBsp = nullptr;
  /// Internal-edge marking that never hides an edge of a brush's shell (not
  /// the original's; off by default, so that .cm output stays the
  /// original's). The original also marks an edge internal when it lies in
  /// a coplanar polygon facing the same way (or the opposite way), which
  /// happens where brushes overlap with coplanar faces: the corner edges of
  /// both copies get marked and a trace-model edge passes through the
  /// corner. With this set, an edge is marked internal only by a polygon
  /// that is not parallel to its own (a concave crease, or an edge lying on
  /// a face that meets its polygon at an angle), and an edge shared by
  /// polygons of different contents (a solid face and a clip face) is never
  /// marked: the rule decides within one contents group, but the flag hides
  /// the edge from every user. It also builds the edge normals of two-sided
  /// polygons as one sheet: the line a two-sided polygon shares with its
  /// reversed copy is not a sharp fold, so its epsilon edge lies 0.25 units
  /// out, not the original's 0.83 (and more where neighbours add to it), and
  /// traces stop 0.25 units from a two-sided surface. And it cuts a polygon
  /// where a vertex of a coplanar polygon lies on its edge (a T-junction:
  /// a face against two, a face chopped where a brush stands on it), so that
  /// the seam is made of shared edges and a point trace cannot pass between
  /// the two (map models only; lt4's world model has half again as many
  /// polygons). The .cm file does not store edge normals: a .cm written from
  /// such a model loads with the original's. See docs/reliability.md and
  /// docs/fidelity.md.
  bool robustEdges = false;
};

/// What buildCollisionModels made.
struct BuildResult {
  /// One model per entity that owns primitives, in entity order (the world
  /// model first).
  std::vector<ModelPtr> models;
  /// Warnings (skipped degenerate brushes, truncated polygons, ...), in the
  /// order they arose; a repeated message is one line with its count.
  std::vector<std::string> warnings;
};

/// Builds one collision model per entity that owns primitives, in entity
/// order, named as the original names them (the "model" key, else "name",
/// else "worldMap" for the first model and "unnamed inline model" for the
/// others), each in its entity's local frame, with the build's warnings.
/// Error: a brush with more than kMaxBrushSides sides (the warnings so far
/// are dropped with the models).
Result<BuildResult> buildCollisionModels(const MapFile& map, const MaterialTable& materials,
                                         const BuildOptions& options = {});

/// What writeCollisionModelForMapEntity made and wrote.
struct EntityModelReport {
  ModelPtr model;  ///< the model written
  /// Build warnings (as BuildResult::warnings).
  std::vector<std::string> warnings;
  /// With EntityModelOptions::testTraceModel: the model as a trace model, or
  /// the Error saying why it cannot be one (not convex, not closed, too many
  /// vertices, edges or polygons; see traceModelFromCollisionModel). That is
  /// a finding, not a failure of the write.
  std::optional<Result<TraceModel>> traceModel;
};

/// Options of writeCollisionModelForMapEntity.
struct EntityModelOptions {
  /// Also convert the model to a trace model (the original's TrmFromModel).
  bool testTraceModel = false;
  /// As BuildOptions::robustEdges.
  bool robustEdges = false;
};

/// The original's WriteCollisionModelForMapEntity: builds the collision
/// model of map.entities[entityIndex] alone (in its local frame; no .proc
/// pruning, which the original only applies while loading a whole map),
/// names it `path` exactly as given (the original names the model after the
/// file it writes), and writes a .cm holding only that model with CRC 0.
/// Returns the model written, its build warnings and (with
/// EntityModelOptions::testTraceModel) the trace-model finding.
/// Errors: no such entity, an entity without brushes or patches, a brush
/// with more than kMaxBrushSides sides, a file that cannot be written.
/// Nothing is written on error (the text goes to a temporary file beside
/// `path` that is then renamed), and no report is returned.
Result<EntityModelReport> writeCollisionModelForMapEntity(const MapFile& map, std::size_t entityIndex,
                                                          const std::string& path,
                                                          const MaterialTable& materials,
                                                          const EntityModelOptions& options = {});

}  // namespace cmkit
