// build.h: building collision models from a parsed map (the original's
// map -> collision model pipeline).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/proc_file.h"
#include "cmkit/result.h"

namespace cmkit {

/// Options of the map -> model build.
struct BuildOptions {
  /// Called with (entities done, entities in all) as the build progresses;
  /// may be empty.
  std::function<void(std::size_t, std::size_t)> progress;
  /// Warnings (skipped degenerate brushes, truncated polygons, ...) are
  /// appended here when not null.
  std::vector<std::string>* warnings = nullptr;
  /// The renderer's BSP of the map's .proc file (loadProcFileForMap), or
  /// null. When set and usable, the world model (the first model built)
  /// drops every solid polygon winding lying entirely in its opaque solid
  /// leaves, as the original does (cm-algorithms.md section 3.7); the count
  /// is ModelStats::procPolygonsRemoved. Must outlive the call.
  const ProcBsp* procBsp = nullptr;
};

/// Builds one collision model per entity that owns primitives, in entity
/// order, named as the original names them (the "model" key, else "name",
/// else "worldMap" for the first model and "unnamed inline model" for the
/// others), each in its entity's local frame.
Result<std::vector<ModelPtr>> buildCollisionModels(const MapFile& map, const MaterialTable& materials,
                                                   const BuildOptions& options = {});

}  // namespace cmkit
