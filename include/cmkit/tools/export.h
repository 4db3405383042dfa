// export.h: collision models and traces as glTF 2.0 (.gltf with an
// embedded base64 buffer, or binary .glb) and Wavefront OBJ (+ .mtl), for
// looking at them in any 3D viewer (and cmkit's web viewer, viewer/).
//
// CONTRACT
// - Coordinates are the map's (z up, map units) in every buffer; the glTF
//   scene's root node "cmkit" turns z-up into glTF's y-up (-90 degrees about
//   x), so accessor min/max are map coordinates.
// - Polygons are triangle fans with flat normals, grouped into one mesh per
//   (model, contents value), with one material per contents value named by
//   its flags ("solid,opaque"). Edges and internal edges are line meshes of
//   their own; each trace is a node with line meshes for its path, trace
//   model, contact marker and contact normal.
// - Every glTF node carries `extras` for viewers: {"kind": "polygons" |
//   "edges" | "internal edges" | "trace", "contents": N, "model": NAME,
//   "modelIndex": I} for model parts, plus "classname": CLASS and "origin":
//   [x,y,z] when the options give them (a map's entities: the model's
//   entity); {"trace": I, "query": LINE, "result": LINE, "fraction": F,
//   "point": [x,y,z], "normal": [x,y,z], "type": T, "modelFeature": N,
//   "trmFeature": N} for traces, plus "entity": NAME when the result names
//   the entity hit (world results).
// - Output is deterministic (same input, same bytes).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "cmkit/result.h"
#include "cmkit/tools/debug_draw.h"

namespace cmkit {

/// What to export.
struct ExportOptions {
  /// Only polygons with these contents.
  std::uint32_t contentMask = contents::kMaskAll;
  /// Export polygon edges as line meshes.
  bool edges = true;
  /// Export internal edges as a separate line mesh.
  bool internalEdges = true;
  /// Where each model is placed (index = model index); models past the end
  /// are at the origin with identity axis. Exported positions are placed.
  std::vector<Placement> placements;
  /// The class name of each model's entity (index = model index; missing or
  /// empty: none), written into the model's glTF extras ("classname").
  std::vector<std::string> classNames;
};

/// The scene as glTF JSON with the buffer embedded as a base64 data URI.
std::string exportGltf(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                       const ExportOptions& options = {});

/// The scene as a binary glTF (.glb).
std::vector<std::uint8_t> exportGlb(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                                    const ExportOptions& options = {});

/// The scene as OBJ text; materials refer to `mtlFileName` (written by
/// exportMtl), lines are "l" elements.
std::string exportObj(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                      const std::string& mtlFileName, const ExportOptions& options = {});

/// The material library for exportObj (one material per contents value and
/// one per line colour).
std::string exportMtl(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                      const ExportOptions& options = {});

/// Writes the scene by the path's extension: .gltf, .glb or .obj (plus a
/// .mtl beside it). Error for another extension or a write failure.
Status saveScene(const std::string& path, std::span<const ModelPtr> models,
                 std::span<const TraceRecord> traces, const ExportOptions& options = {});

}  // namespace cmkit
