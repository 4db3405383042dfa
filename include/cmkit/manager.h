// manager.h: a collection of collision models addressed by handles (the
// original's collision model manager, without its global state).
//
// A ModelManager owns models and hands out ModelHandles, small integers that
// index its table. After loadMap, handle 0 is the world model (the map's
// first model) and the others follow in entity order. Handles are never
// reused while the manager lives, except that loadMap() and clear() start
// the table again: freeing one model leaves every other handle valid.
//
// The manager only manages: a model's own data and functions (name, bounds,
// polygonWinding, modelStatistics, traceModelFromCollisionModel, ...) are
// reached through get() or require().
//
// Thread safety: every member function may be called from any thread at any
// time. Models are immutable and handed out as shared_ptrs, so a model being
// queried stays alive even if another thread frees it or loads a new map;
// loading (parsing and building) happens outside the manager's lock, so
// queries on already loaded models never wait for a load.
#pragma once

#include <cstdint>
#include <memory>
#include <shared_mutex>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/contents.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/model.h"
#include "cmkit/ray_index.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// A handle to a model of a ModelManager: an index into its table.
struct ModelHandle {
  std::int32_t index = -1;  ///< -1: no model

  /// True when the handle names a model slot (it may have been freed since).
  constexpr bool valid() const { return index >= 0; }
  /// Handles order by index.
  constexpr auto operator<=>(const ModelHandle&) const = default;
};

/// The world model's handle after ModelManager::loadMap.
inline constexpr ModelHandle kWorldModelHandle{0};

/// How ModelManager::loadMap gets its models.
struct LoadMapOptions {
  /// Build from the map even if NAME.cm next to it matches the map's CRC.
  bool forceRebuild = false;
  /// After building, write NAME.cm next to the map, as the original does
  /// (off by default: a library should not write files unasked).
  bool writeCmFile = false;
  /// Read NAME.proc beside the map when it exists and prune the world model
  /// with its BSP, as the original does (ignored when build.procBsp is set).
  /// A malformed .proc is an error.
  bool useProcFile = true;
  /// Passed to buildCollisionModels.
  BuildOptions build;
};

/// What loadMap did.
struct LoadMapResult {
  std::vector<ModelHandle> handles;  ///< one per model, world first
  bool fromCmFile = false;           ///< true: NAME.cm was loaded instead of building
  std::string cmPath;                ///< the .cm file loaded or written, if any
  std::uint32_t geometryCrc = 0;     ///< the map's geometry CRC
  std::string procPath;              ///< the .proc that pruned the world model; empty: none
  int procPolygonsRemoved = 0;       ///< world windings it dropped
  /// Warnings of the .proc reader and of the build (BuildResult::warnings);
  /// empty when the models came from NAME.cm.
  std::vector<std::string> warnings;
};

/// How ModelManager::loadModel converts a mesh file.
struct LoadModelOptions {
  /// How the mesh file is read.
  MeshLoadOptions mesh;
  /// How the mesh becomes a collision model (the build's warnings are not
  /// kept: loadMeshModel returns them).
  MeshBuildOptions build;
};

/// One line of ModelManager::list.
struct ModelListEntry {
  /// The model's handle.
  ModelHandle handle;
  /// The model's name.
  std::string name;
  /// The model.
  ModelPtr model;
};

/// A set of collision models addressed by handles. See the file comment for
/// the handle and threading rules.
class ModelManager {
 public:
  ModelManager() = default;
  ModelManager(const ModelManager&) = delete;
  ModelManager& operator=(const ModelManager&) = delete;

  /// Loads a map's models, replacing every model of the manager: NAME.cm
  /// next to the map when its CRC equals the map's geometry CRC (or is 0)
  /// and options.forceRebuild is off, else built with buildCollisionModels
  /// (the world model pruned with NAME.proc when present, see useProcFile).
  /// On error the manager is unchanged.
  Result<LoadMapResult> loadMap(const std::string& mapPath, const MaterialTable& materials,
                                const LoadMapOptions& options = {});
  /// Loads every model of a .cm file and adds them (handles in file order).
  /// On error nothing is added.
  Result<std::vector<ModelHandle>> loadCm(const std::string& path, const MaterialTable& materials);
  /// The original's LoadModel: the handle of the model named `name` when
  /// the manager has one; else NAME.cm (`name` with its extension replaced)
  /// when it exists and holds a model of that name (all its models are
  /// added, as the original adds the whole file); else the mesh file `name`
  /// converted into a collision model (loadMeshModel, named `name`). Errors:
  /// a malformed NAME.cm, a mesh that cannot be read (or cmkit built without
  /// assimp), neither file. On error nothing is added.
  Result<ModelHandle> loadModel(const std::string& name, const MaterialTable& materials,
                                const LoadModelOptions& options = {});
  /// Adds a model built elsewhere.
  ModelHandle add(ModelPtr model);
  /// Adds the collision model of a trace model (the original's
  /// SetupTrmModel): any number may exist at once. See
  /// collisionModelFromTraceModel.
  ModelHandle addTraceModel(const TraceModel& trm, std::uint32_t contents = contents::kSolid,
                            std::string material = {});

  /// The handle of the first model with this name (case-sensitive), or
  /// "#N" for handle N. An unknown name is an error (never the world).
  Result<ModelHandle> find(std::string_view name) const;
  /// The model, or nullptr for a handle that is out of range or freed.
  ModelPtr get(ModelHandle handle) const;
  /// The model, or an error naming the bad handle.
  Result<ModelPtr> require(ModelHandle handle) const;

  /// Frees one model; its handle becomes invalid, all others stay valid.
  Status free(ModelHandle handle);
  /// Frees every model (handles start at 0 again).
  void clear();
  /// The live models in handle order.
  std::vector<ModelListEntry> list() const;
  /// Number of live models.
  std::size_t size() const;

  /// The model's RayIndex (ray_index.h), built on first use (outside the
  /// lock) and kept until the model is freed or replaced. Two threads asking
  /// for a new one at once may both build it; one is kept for both.
  Result<std::shared_ptr<const RayIndex>> rayIndex(ModelHandle handle) const;

 private:
  std::string handleError(ModelHandle handle) const;  // call with the lock held

  mutable std::shared_mutex mutex_;
  std::vector<ModelPtr> models_;  // nullptr: freed
  std::unordered_map<std::string, std::vector<std::int32_t>> byName_;
  mutable std::unordered_map<std::int32_t, std::shared_ptr<const RayIndex>> rayIndexes_;  // by handle
};

}  // namespace cmkit
