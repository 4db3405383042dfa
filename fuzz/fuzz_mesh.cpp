// Fuzz target: mesh file bytes -> assimp (through loadMeshMemory) -> the
// mesh builder -> models (validated) -> queries.
//
// The first byte of an input picks the format assimp is told (the name's
// extension) and whether every surface is made solid; the rest is the file.
#include <array>
#include <cstddef>
#include <span>
#include <string_view>

#include "cmkit/contents.h"
#include "cmkit/mesh.h"
#include "fuzz_common.h"

namespace {

/// The names whose extensions select the importers fuzzed: OBJ, glTF and
/// GLB, the formats cmkit's users bring most (the other formats assimp
/// reads are not fuzzed; its PLY reader hangs on some malformed headers,
/// which loadMeshMemory and loadMeshFile check themselves: src/io/mesh_checks.h,
/// docs/reliability.md). Files an OBJ or a .gltf refers to are not there
/// in memory; they still parse.
constexpr std::array<std::string_view, 3> kNames = {"fuzz.obj", "fuzz.gltf", "fuzz.glb"};

/// Per-exec cost cap of this target (not of the library): building a model
/// is superlinear in its triangles, and the point is odd input, not big
/// input (the builder's size behaviour is covered by the mesh build tests).
constexpr std::size_t kMaxTriangles = 4096;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2 || size > cmkit::fuzz::kMaxInputBytes) return 0;
  const std::string_view name = kNames[data[0] % kNames.size()];
  // The byte's upper bits: the materials' contents (unknown names have none
  // by the default rules) or solid for every surface.
  const bool forceSolid = (data[0] / kNames.size()) % 2 == 1;
  const auto bytes = std::as_bytes(std::span<const std::uint8_t>(data + 1, size - 1));
  auto mesh = cmkit::loadMeshMemory(bytes, name);
  if (!mesh) return 0;
  std::size_t triangles = 0;
  for (const cmkit::MeshSurface& s : mesh->surfaces) triangles += s.indices.size() / 3;
  if (triangles > kMaxTriangles) return 0;
  cmkit::MeshBuildOptions options;
  if (forceSolid) options.contents = cmkit::contents::kSolid;
  auto built = cmkit::buildCollisionModelFromTriangles(*mesh, "fuzz", cmkit::MaterialTable{}, options);
  if (!built) return 0;
  cmkit::fuzz::requireValid(*built->model, "the mesh builder");
  const cmkit::ModelPtr models[] = {built->model};
  cmkit::fuzz::exerciseModels(models);
  return 0;
}
