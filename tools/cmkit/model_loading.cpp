#include "model_loading.h"

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"

namespace cmkit::cli {

Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir) {
  MaterialTable materials;
  if (!materialsDir.empty()) {
    if (Status s = materials.addMtrDirectory(materialsDir); !s) return s.error();
  }
  auto endsWith = [&](const char* ext) {
    const std::string e(ext);
    return path.size() >= e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (endsWith(".cm")) {
    auto file = loadCmFile(path, materials);
    if (!file) return file.error();
    return std::move(file->models);
  }
  if (endsWith(".map")) {
    auto map = loadMapFile(path);
    if (!map) return map.error();
    return buildCollisionModels(*map, materials);
  }
  return Error{"expected a .map or .cm file", path};
}

}  // namespace cmkit::cli
