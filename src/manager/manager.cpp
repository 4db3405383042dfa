// The model manager: a handle table of shared, immutable models guarded by a
// shared mutex. Loading and building happen outside the lock.
#include "cmkit/manager.h"

#include <charconv>
#include <filesystem>
#include <iterator>
#include <mutex>
#include <new>
#include <optional>

#include "cmkit/cm_file.h"

namespace cmkit {

namespace {

// NAME.map -> NAME.cm (any extension replaced; none: appended).
std::string cmPathForMap(const std::string& mapPath) {
  std::filesystem::path p(mapPath);
  p.replace_extension(".cm");
  return p.string();
}

/// Runs a loading step and turns what it could throw (running out of memory
/// on a huge file, a filesystem error) into an Error: the manager's loaders,
/// like every loader of cmkit, never throw.
template <class F>
auto withoutExceptions(const std::string& path, F&& step) -> decltype(step()) {
  try {
    return step();
  } catch (const std::bad_alloc&) {
    return Error("out of memory while loading", path);
  } catch (const std::exception& e) {
    return Error(e.what(), path);
  }
}

}  // namespace

std::string ModelManager::handleError(ModelHandle handle) const {
  if (!handle.valid() || std::size_t(handle.index) >= models_.size())
    return "no model with handle " + std::to_string(handle.index);
  return "model " + std::to_string(handle.index) + " has been freed";
}

Result<LoadMapResult> ModelManager::loadMap(const std::string& mapPath, const MaterialTable& materials,
                                            const LoadMapOptions& options) {
  return withoutExceptions(mapPath, [&]() -> Result<LoadMapResult> {
    Result<MapFile> map = loadMapFile(mapPath);
    if (!map) return map.error();
    LoadMapResult result;
    result.geometryCrc = map->geometryCrc;
    std::vector<ModelPtr> models;
    const std::string cmPath = cmPathForMap(mapPath);
    // The original's LoadMap: a .cm written for exactly this geometry is used
    // instead of building. A .cm that fails to parse is ignored (rebuilt).
    std::error_code ec;
    if (!options.forceRebuild && std::filesystem::exists(cmPath, ec)) {
      Result<std::uint32_t> crc = readCmFileCrc(cmPath);
      if (crc && (*crc == map->geometryCrc || *crc == 0)) {
        Result<CmFile> cm = loadCmFile(cmPath, materials);
        if (cm) {
          models = std::move(cm->models);
          result.fromCmFile = true;
          result.cmPath = cmPath;
        }
      }
    }
    if (!result.fromCmFile) {
      // NAME.proc prunes the world model, as in the original (unless the
      // caller gave a BSP or turned it off).
      BuildOptions build = options.build;
      std::optional<ProcBsp> proc;
      if (!build.procBsp && options.useProcFile) {
        Result<std::optional<ProcBsp>> loaded = loadProcFileForMap(mapPath, &result.warnings);
        if (!loaded) return loaded.error();
        proc = std::move(*loaded);
        if (proc && proc->usable()) build.procBsp = &*proc;
      }
      if (build.procBsp && build.procBsp->usable()) result.procPath = build.procBsp->fileName;
      Result<BuildResult> built = buildCollisionModels(*map, materials, build);
      if (!built) return built.error();
      if (!built->models.empty())
        result.procPolygonsRemoved = built->models.front()->stats().procPolygonsRemoved;
      models = std::move(built->models);
      result.warnings.insert(result.warnings.end(), std::make_move_iterator(built->warnings.begin()),
                             std::make_move_iterator(built->warnings.end()));
      if (options.writeCmFile) {
        Status saved = saveCmFile(cmPath, models, map->geometryCrc);
        if (!saved) return saved.error();
        result.cmPath = cmPath;
      }
    }
    std::unique_lock lock(mutex_);
    models_.clear();
    byName_.clear();
    rayIndexes_.clear();
    for (ModelPtr& m : models) {
      const auto index = std::int32_t(models_.size());
      byName_[m->name()].push_back(index);
      models_.push_back(std::move(m));
      result.handles.push_back(ModelHandle{index});
    }
    return result;
  });
}

Result<std::vector<ModelHandle>> ModelManager::loadCm(const std::string& path,
                                                      const MaterialTable& materials) {
  return withoutExceptions(path, [&]() -> Result<std::vector<ModelHandle>> {
    Result<CmFile> cm = loadCmFile(path, materials);
    if (!cm) return cm.error();
    std::vector<ModelHandle> handles;
    std::unique_lock lock(mutex_);
    for (ModelPtr& m : cm->models) {
      const auto index = std::int32_t(models_.size());
      byName_[m->name()].push_back(index);
      models_.push_back(std::move(m));
      handles.push_back(ModelHandle{index});
    }
    return handles;
  });
}

Result<ModelHandle> ModelManager::loadModel(const std::string& name, const MaterialTable& materials,
                                            const LoadModelOptions& options) {
  return withoutExceptions(name, [&]() -> Result<ModelHandle> {
    // Already loaded; checked again under the write lock before adding.
    auto loaded = [&]() -> std::optional<ModelHandle> {
      const auto it = byName_.find(name);
      if (it == byName_.end()) return std::nullopt;
      for (const std::int32_t i : it->second) {
        if (models_[static_cast<std::size_t>(i)]) return ModelHandle{i};
      }
      return std::nullopt;
    };
    {
      std::shared_lock lock(mutex_);
      if (auto h = loaded()) return *h;
    }
    std::vector<ModelPtr> models;
    std::size_t wanted = 0;
    const std::string cmPath = cmPathForMap(name);
    std::error_code ec;
    if (cmPath != name && std::filesystem::is_regular_file(cmPath, ec)) {
      Result<CmFile> cm = loadCmFile(cmPath, materials);
      if (!cm) return cm.error();
      for (std::size_t i = 0; i < cm->models.size(); ++i) {
        if (cm->models[i]->name() == name) {
          models = std::move(cm->models);
          wanted = i;
          break;
        }
      }
    }
    if (models.empty()) {
      Result<MeshBuildResult> mesh = loadMeshModel(name, materials, options.mesh, options.build);
      if (!mesh) return mesh.error();
      models.push_back(std::move(mesh->model));
    }
    std::unique_lock lock(mutex_);
    if (auto h = loaded()) return *h;
    ModelHandle result;
    for (std::size_t i = 0; i < models.size(); ++i) {
      const auto index = std::int32_t(models_.size());
      byName_[models[i]->name()].push_back(index);
      models_.push_back(std::move(models[i]));
      if (i == wanted) result = ModelHandle{index};
    }
    return result;
  });
}

ModelHandle ModelManager::add(ModelPtr model) {
  if (!model) return {};
  std::unique_lock lock(mutex_);
  const auto index = std::int32_t(models_.size());
  byName_[model->name()].push_back(index);
  models_.push_back(std::move(model));
  return ModelHandle{index};
}

ModelHandle ModelManager::addTraceModel(const TraceModel& trm, std::uint32_t contents, std::string material) {
  return add(collisionModelFromTraceModel(trm, contents, std::move(material)));
}

Result<ModelHandle> ModelManager::find(std::string_view name) const {
  std::shared_lock lock(mutex_);
  if (auto it = byName_.find(std::string(name)); it != byName_.end()) {
    for (const std::int32_t index : it->second)
      if (models_[std::size_t(index)]) return ModelHandle{index};
  }
  if (name.size() > 1 && name[0] == '#') {  // "#N": handle N
    std::int32_t index = -1;
    const auto r = std::from_chars(name.data() + 1, name.data() + name.size(), index);
    if (r.ec == std::errc() && r.ptr == name.data() + name.size() && index >= 0 &&
        std::size_t(index) < models_.size() && models_[std::size_t(index)])
      return ModelHandle{index};
  }
  return Error("no model named \"" + std::string(name) + "\"");
}

ModelPtr ModelManager::get(ModelHandle handle) const {
  std::shared_lock lock(mutex_);
  if (!handle.valid() || std::size_t(handle.index) >= models_.size()) return nullptr;
  return models_[std::size_t(handle.index)];
}

Result<ModelPtr> ModelManager::require(ModelHandle handle) const {
  std::shared_lock lock(mutex_);
  if (handle.valid() && std::size_t(handle.index) < models_.size() && models_[std::size_t(handle.index)])
    return models_[std::size_t(handle.index)];
  return Error(handleError(handle));
}

Status ModelManager::free(ModelHandle handle) {
  ModelPtr released;  // destroyed after the lock is released
  std::unique_lock lock(mutex_);
  if (!handle.valid() || std::size_t(handle.index) >= models_.size() || !models_[std::size_t(handle.index)])
    return Error(handleError(handle));
  released = std::move(models_[std::size_t(handle.index)]);
  rayIndexes_.erase(handle.index);
  auto it = byName_.find(released->name());
  if (it != byName_.end()) {
    std::erase(it->second, handle.index);
    if (it->second.empty()) byName_.erase(it);
  }
  return Ok{};
}

void ModelManager::clear() {
  std::vector<ModelPtr> released;
  std::unique_lock lock(mutex_);
  released.swap(models_);
  byName_.clear();
  rayIndexes_.clear();
}

Result<std::shared_ptr<const RayIndex>> ModelManager::rayIndex(ModelHandle handle) const {
  ModelPtr model;
  {
    std::shared_lock lock(mutex_);
    if (!handle.valid() || std::size_t(handle.index) >= models_.size() || !models_[std::size_t(handle.index)])
      return Error(handleError(handle));
    if (auto it = rayIndexes_.find(handle.index); it != rayIndexes_.end()) return it->second;
    model = models_[std::size_t(handle.index)];
  }
  auto built = std::make_shared<const RayIndex>(*model);  // outside the lock: queries never wait
  std::unique_lock lock(mutex_);
  // The handle may have been freed or reused meanwhile: keep the index only
  // for the same model.
  if (std::size_t(handle.index) >= models_.size() || models_[std::size_t(handle.index)] != model)
    return built;
  return rayIndexes_.try_emplace(handle.index, std::move(built)).first->second;
}

std::vector<ModelListEntry> ModelManager::list() const {
  std::shared_lock lock(mutex_);
  std::vector<ModelListEntry> out;
  for (std::size_t i = 0; i < models_.size(); ++i) {
    if (models_[i]) out.push_back({ModelHandle{std::int32_t(i)}, models_[i]->name(), models_[i]});
  }
  return out;
}

std::size_t ModelManager::size() const {
  std::shared_lock lock(mutex_);
  std::size_t n = 0;
  for (const ModelPtr& m : models_) n += m != nullptr;
  return n;
}

}  // namespace cmkit
