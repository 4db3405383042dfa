// Mesh files -> TriangleMesh through Debian's assimp (the only file that
// includes assimp; without it, loadMeshFile says cmkit was built without it).
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <string_view>

#include "cmkit/mesh.h"
#include "cmkit/tolerances.h"
#include "mesh_checks.h"

#ifdef CMKIT_HAVE_ASSIMP
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#endif

namespace cmkit {

namespace {

std::string lowerExtension(std::string_view path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

#ifdef CMKIT_HAVE_ASSIMP

/// Collects the triangles of every mesh below a node, with the node
/// transforms applied.
class SceneReader {
 public:
  SceneReader(const aiScene& scene, const Mat3& frame, Real scale)
      : scene_(scene), frame_(frame), scale_(scale) {}

  void visit(const aiNode& node, const aiMatrix4x4& parent, int depth) {
    if (depth > kMaxNodeDepth) return;
    const aiMatrix4x4 transform = parent * node.mTransformation;
    // A mirroring transform turns the triangles' facing around.
    const bool mirrored = transform.Determinant() < 0;
    for (unsigned int m = 0; m < node.mNumMeshes; ++m) {
      if (node.mMeshes[m] < scene_.mNumMeshes) addMesh(*scene_.mMeshes[node.mMeshes[m]], transform, mirrored);
    }
    for (unsigned int c = 0; c < node.mNumChildren; ++c) {
      if (node.mChildren[c]) visit(*node.mChildren[c], transform, depth + 1);
    }
  }

  TriangleMesh mesh;

 private:
  /// Deeper node trees are not walked (a guard against cyclic or absurd files).
  static constexpr int kMaxNodeDepth = 1000;

  void addMesh(const aiMesh& m, const aiMatrix4x4& transform, bool mirrored) {
    if (!m.mVertices) return;
    MeshSurface surface;
    if (m.mMaterialIndex < scene_.mNumMaterials && scene_.mMaterials[m.mMaterialIndex]) {
      aiString name;
      if (scene_.mMaterials[m.mMaterialIndex]->Get(AI_MATKEY_NAME, name) == AI_SUCCESS) {
        surface.material.assign(name.C_Str(), name.length);
      }
    }
    const auto base = static_cast<std::uint32_t>(mesh.positions.size());
    for (unsigned int v = 0; v < m.mNumVertices; ++v) {
      const aiVector3D p = transform * m.mVertices[v];
      mesh.positions.push_back(Vec3{p.x * scale_, p.y * scale_, p.z * scale_} * frame_);
    }
    for (unsigned int f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines (polygons were triangulated)
      const std::array<unsigned int, 3> order =
          mirrored ? std::array<unsigned int, 3>{0, 2, 1} : std::array<unsigned int, 3>{0, 1, 2};
      for (const unsigned int k : order) surface.indices.push_back(base + face.mIndices[k]);
    }
    if (!surface.indices.empty()) mesh.surfaces.push_back(std::move(surface));
  }

  const aiScene& scene_;
  Mat3 frame_;
  Real scale_;
};

/// Whether every face of every mesh of a scene has vertices and indexes
/// its mesh's vertices.
bool facesInRange(const aiScene& scene) {
  for (unsigned int m = 0; m < scene.mNumMeshes; ++m) {
    const aiMesh* mesh = scene.mMeshes[m];
    if (!mesh) return false;
    if (mesh->mNumFaces > 0 && !mesh->mFaces) return false;
    for (unsigned int f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices == 0 || !face.mIndices)
        return false;  // Triangulate reads an empty face's first index
      for (unsigned int k = 0; k < face.mNumIndices; ++k)
        if (face.mIndices[k] >= mesh->mNumVertices) return false;
    }
  }
  return true;
}

/// Reads a scene with assimp from a file (`bytes` empty) or from memory
/// (`bytes`, with `path` as the name whose extension tells the format).
Result<TriangleMesh> readWithAssimp(const std::string& path, std::span<const std::byte> bytes,
                                    const MeshLoadOptions& options) {
  Assimp::Importer importer;
  // Points and lines are dropped by SortByPType; polygons become triangles.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  std::string hint = lowerExtension(path);
  if (!hint.empty()) hint.erase(0, 1);  // assimp's hint is the extension without its dot
  // The scene is read without post-processing first and its faces checked
  // (facesInRange): assimp 5.2's readers leave some malformed files' faces
  // empty or with indices past their meshes' vertices (PLY numbers a
  // mutation garbled, found by fuzzing), which Triangulate reads past.
  const aiScene* scene = bytes.empty()
                             ? importer.ReadFile(path, 0)
                             : importer.ReadFileFromMemory(bytes.data(), bytes.size(), 0, hint.c_str());
  if (scene && scene->mRootNode && !facesInRange(*scene))
    return Error("the mesh file has a face without vertices or with a vertex index out of range", path);
  if (scene && scene->mRootNode)
    scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_SortByPType);
  if (!scene || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "unknown reason";
    return Error("assimp cannot read this mesh file: " + why, path);
  }
  MeshUpAxis up = options.up;
  if (up == MeshUpAxis::Auto) {
    const std::string ext = lowerExtension(path);
    up = ext == ".gltf" || ext == ".glb" ? MeshUpAxis::Y : MeshUpAxis::Z;
  }
  // Rows are the images of the x, y and z axes (mat3.h): y up -> (x, -z, y).
  const Mat3 frame =
      up == MeshUpAxis::Y ? Mat3{Vec3{1, 0, 0}, Vec3{0, 0, 1}, Vec3{0, -1, 0}} : Mat3::identity();
  SceneReader reader(*scene, frame, options.scale);
  reader.visit(*scene->mRootNode, aiMatrix4x4(), 0);
  if (reader.mesh.surfaces.empty()) return Error("the mesh file has no triangles", path);
  for (const Vec3& p : reader.mesh.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return Error("the mesh file has a vertex that is not a finite number", path);
    }
  }
  return std::move(reader.mesh);
}

/// The first `limit` bytes of a mesh file, or all of it (for the checks of
/// readGuarded).
std::string fileBytes(const std::string& path, std::size_t limit = std::string::npos) {
  std::ifstream in(path, std::ios::binary);
  if (limit == std::string::npos)
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  std::string head(limit, '\0');
  in.read(head.data(), static_cast<std::streamsize>(limit));
  head.resize(static_cast<std::size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return head;
}

/// readWithAssimp with what assimp throws turned into errors, after the
/// checks of PLY and GLB files (mesh_checks.h), on some malformed ones of
/// which assimp hangs, crashes or takes gigabytes. `bytes` empty: the file
/// at `path`.
Result<TriangleMesh> readGuarded(const std::string& path, std::span<const std::byte> bytes,
                                 const MeshLoadOptions& options) {
  // A PLY file (by its name) or binary glTF (by its magic, whatever its
  // name) is read whole for its checks and handed to assimp from memory
  // (both formats stand alone: nothing beside them to read).
  const bool ply = lowerExtension(path) == ".ply";
  const std::string file =
      bytes.empty() && (ply || fileBytes(path, 4) == "glTF") ? fileBytes(path) : std::string{};
  if (!file.empty()) bytes = std::as_bytes(std::span<const char>(file.data(), file.size()));
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  std::string why = ply ? plyProblem(text) : std::string{};
  if (why.empty()) why = glbProblem(text);
  if (!why.empty()) return Error(why, path);
  try {
    return readWithAssimp(path, bytes, options);
  } catch (const std::bad_alloc&) {
    return Error("out of memory while reading the mesh file", path);
  } catch (const std::exception& e) {
    return Error(std::string("assimp cannot read this mesh file: ") + e.what(), path);
  } catch (...) {
    return Error("assimp cannot read this mesh file (unknown error)", path);
  }
}

#else

Error withoutAssimp(const std::string& path) {
  return Error(
      "cmkit was built without assimp, so it cannot read mesh files: install Debian's libassimp-dev "
      "and rebuild (or build the model with buildCollisionModelFromTriangles)",
      path);
}

#endif

}  // namespace

bool meshLoaderAvailable() {
#ifdef CMKIT_HAVE_ASSIMP
  return true;
#else
  return false;
#endif
}

bool isMeshFileName(std::string_view path) {
  static constexpr std::array<std::string_view, 12> kExtensions = {
      ".obj", ".gltf", ".glb", ".ase", ".lwo", ".ma", ".fbx", ".ply", ".dae", ".3ds", ".stl", ".off"};
  const std::string ext = lowerExtension(path);
  return std::find(kExtensions.begin(), kExtensions.end(), ext) != kExtensions.end();
}

Result<TriangleMesh> loadMeshFile(const std::string& path, const MeshLoadOptions& options) {
  if (!(std::isfinite(options.scale) && options.scale > 0))
    return Error("the mesh scale must be a positive finite number", path);
#ifdef CMKIT_HAVE_ASSIMP
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return Error("cannot open the mesh file: no such file", path);
  if (!std::filesystem::is_regular_file(path, ec))
    return Error("cannot read the mesh file: not a regular file", path);
  return readGuarded(path, {}, options);
#else
  return withoutAssimp(path);
#endif
}

Result<TriangleMesh> loadMeshMemory(std::span<const std::byte> bytes, std::string_view name,
                                    const MeshLoadOptions& options) {
  const std::string path(name);
  if (!(std::isfinite(options.scale) && options.scale > 0))
    return Error("the mesh scale must be a positive finite number", path);
  if (bytes.empty()) return Error("the mesh data is empty", path);
  if (bytes.size() > kMaxMeshMemoryBytes) return Error("the mesh data is larger than 1 GiB", path);
#ifdef CMKIT_HAVE_ASSIMP
  return readGuarded(path, bytes, options);
#else
  return withoutAssimp(path);
#endif
}

Result<MeshBuildResult> loadMeshModel(const std::string& path, const MaterialTable& materials,
                                      const MeshLoadOptions& loadOptions,
                                      const MeshBuildOptions& buildOptions) {
  Result<TriangleMesh> mesh = loadMeshFile(path, loadOptions);
  if (!mesh) return mesh.error();
  return buildCollisionModelFromTriangles(*mesh, path, materials, buildOptions);
}

}  // namespace cmkit
