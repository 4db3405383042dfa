// mesh.h: triangle meshes (render models) as collision models (the
// original's LoadModel fallback, which converts a render model when no .cm
// file holds the model).
//
// Two layers: buildCollisionModelFromTriangles takes positions and indexed
// triangles grouped in surfaces (one material each), the path any engine can
// call with its own mesh data; loadMeshFile reads a mesh file (OBJ, glTF/GLB,
// ASE, LWO, FBX, PLY, ... through Debian's assimp) into that form. The model
// goes through the same steps as a map entity: vertex and edge welding,
// polygon merging, internal edges, the axial BSP tree.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/materials.h"
#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/result.h"

namespace cmkit {

/// Triangles sharing one material (a render model's surface).
struct MeshSurface {
  /// The material name, matched by the material rules (materials.h) like a
  /// brush side's: its contents decide whether (and how) the surface collides.
  std::string material;
  /// Three indices into TriangleMesh::positions per triangle, counter-clockwise
  /// seen from the front (the side the collision polygon faces: the OBJ and
  /// glTF convention).
  std::vector<std::uint32_t> indices;
};

/// A triangle mesh in model space.
struct TriangleMesh {
  /// Vertex positions.
  std::vector<Vec3> positions;
  /// Triangles grouped by material.
  std::vector<MeshSurface> surfaces;
};

/// Options of buildCollisionModelFromTriangles.
struct MeshBuildOptions {
  /// When set, every surface gets these contents instead of its material's
  /// (for meshes without Doom 3 materials); collision surfaces still decide
  /// which surfaces are used.
  std::optional<std::uint32_t> contents;
  /// As BuildOptions::robustEdges (not the original's; off by default):
  /// internal edges only from non-parallel polygons, and the edges of
  /// two-sided surfaces built as one sheet, so that traces stop 0.25 units
  /// from them instead of up to 0.83 (the original's sharp-edge rule applied
  /// to a triangle and its reversed copy).
  bool robustEdges = false;
};

/// What buildCollisionModelFromTriangles (and loadMeshModel) made.
struct MeshBuildResult {
  /// The collision model.
  ModelPtr model;
  /// Warnings (degenerate triangles dropped, ...), in the order they arose.
  std::vector<std::string> warnings;
};

/// Builds the collision model of a triangle mesh, as the original converts
/// a render model: every triangle of every surface whose material has
/// contents becomes a polygon, or, if any surface's material is a collision
/// surface (the .mtr keyword "collision"), only the triangles of those
/// surfaces. Triangles with a zero normal are skipped (a warning counts
/// them). The model is named `name` (the original uses the file name).
/// Returns the model and the build's warnings.
/// Errors: an index out of range, a surface whose index count is not a
/// multiple of 3, a position that is not finite.
Result<MeshBuildResult> buildCollisionModelFromTriangles(const TriangleMesh& mesh, std::string name,
                                                         const MaterialTable& materials,
                                                         const MeshBuildOptions& options = {});

/// How loadMeshFile places the file's coordinates in Doom's frame (z up).
enum class MeshUpAxis {
  Auto,  ///< glTF/GLB (y up by definition) are converted as Y; every other format as Z
  Z,     ///< coordinates as written
  Y,     ///< y up: (x, y, z) becomes (x, -z, y), as Blender imports glTF
};

/// Options of loadMeshFile.
struct MeshLoadOptions {
  /// Which axis of the file is up.
  MeshUpAxis up = MeshUpAxis::Auto;
  Real scale = 1;  ///< multiplies every coordinate (after the axis change)
};

/// True when cmkit was built with assimp (loadMeshFile can read files).
bool meshLoaderAvailable();

/// True when the path's extension is one of the mesh formats cmkit offers
/// (.obj .gltf .glb .ase .lwo .ma .fbx .ply .dae .3ds .stl .off, any case);
/// whether assimp reads a given file is only known by loading it.
bool isMeshFileName(std::string_view path);

/// Reads a mesh file with assimp: every mesh of every node (with the node
/// transforms applied), its triangles (polygons are triangulated; points and
/// lines dropped) as one surface named after its material. Errors: cmkit was
/// built without assimp, the file cannot be read or parsed (assimp's message
/// with the file name), no triangles, non-finite coordinates.
Result<TriangleMesh> loadMeshFile(const std::string& path, const MeshLoadOptions& options = {});

/// loadMeshFile for a mesh file's bytes already in memory (an archive's
/// entry, a download, Python bytes): `name`'s extension says the format
/// (as isMeshFileName; "crate.glb", ".obj") and MeshUpAxis::Auto reads it;
/// errors name `name`. Files the mesh refers to (an OBJ's .mtl, a .gltf's
/// external buffers) cannot be read from memory: use self-contained
/// formats (GLB, glTF with data: URIs, OBJ whose materials are only
/// named). Inputs over kMaxMeshMemoryBytes are refused.
Result<TriangleMesh> loadMeshMemory(std::span<const std::byte> bytes, std::string_view name,
                                    const MeshLoadOptions& options = {});

/// The largest input loadMeshMemory takes (1 GiB): assimp's buffer length
/// is 32-bit on some platforms.
inline constexpr std::size_t kMaxMeshMemoryBytes = std::size_t(1) << 30;

/// loadMeshFile, then buildCollisionModelFromTriangles with the path as the
/// model name: the model and its build warnings.
Result<MeshBuildResult> loadMeshModel(const std::string& path, const MaterialTable& materials,
                                      const MeshLoadOptions& loadOptions = {},
                                      const MeshBuildOptions& buildOptions = {});

}  // namespace cmkit
