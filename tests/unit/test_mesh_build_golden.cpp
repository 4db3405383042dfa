// Building from triangles keeps its exact output while it gets faster: models
// of generated meshes (welding near the weld distance, coplanar triangles that
// merge, deep axial trees, two-sided and mixed materials), hashed as .cm text
// and compared with the hashes the build made before the speed work (commit
// 22f7167; docs/performance.md, "Building from triangles"). A failure prints the new
// hash: a changed hash means a changed model, which this work must not make.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cmkit/cm_file.h"
#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/tolerances.h"

namespace cmkit {
namespace {

/// splitmix64: the same numbers on every platform and standard library.
struct Rng {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * double(next() >> 11) * 0x1.0p-53; }
};

constexpr const char* kSolid = "textures/golden/solid";
constexpr const char* kTwoSided = "textures/golden/twosided";
constexpr const char* kClip = "textures/golden/clip";

MaterialTable goldenMaterials() {
  MaterialTable materials;
  materials.addMtrText(
      std::string(kSolid) + " { }\n" + kTwoSided + " { twosided }\n" + kClip + " { playerclip }\n",
      "golden.mtr");
  return materials;
}

/// A terrain of quads (flat in patches, so that coplanar triangles merge)
/// whose corners are repeated for every quad with small offsets, some within
/// the weld distance and some just beyond it; then boxes scattered over it.
TriangleMesh goldenMesh(std::uint64_t seed, int gridSize, int numBoxes) {
  Rng rng{seed};
  TriangleMesh mesh;
  std::vector<std::uint32_t> terrain;
  std::vector<std::uint32_t> boxes;
  auto height = [&](int x, int y) { return ((x / 4 + y / 3) % 3 == 0) ? 0.0 : 8.0 * ((x * 7 + y * 3) % 5); };
  auto jitter = [&] {
    const double r = rng.uniform(0, 1);
    if (r < 0.6) return 0.0;
    if (r < 0.9) return rng.uniform(-0.09, 0.09);  // welded
    return rng.uniform(-0.12, 0.12);               // sometimes not
  };
  auto corner = [&](int x, int y) {
    mesh.positions.push_back(
        {Real(x * 32 + jitter()), Real(y * 32 + jitter()), Real(height(x, y) + jitter())});
    return std::uint32_t(mesh.positions.size() - 1);
  };
  for (int y = 0; y < gridSize; ++y) {
    for (int x = 0; x < gridSize; ++x) {
      const std::uint32_t a = corner(x, y), b = corner(x + 1, y), c = corner(x + 1, y + 1),
                          d = corner(x, y + 1);
      terrain.insert(terrain.end(), {a, b, c, a, c, d});
    }
  }
  for (int i = 0; i < numBoxes; ++i) {
    const double x = rng.uniform(0, gridSize * 32.0), y = rng.uniform(0, gridSize * 32.0);
    const double z = rng.uniform(0, 64), s = rng.uniform(4, 40);
    const auto base = std::uint32_t(mesh.positions.size());
    for (int k = 0; k < 8; ++k)
      mesh.positions.push_back(
          {Real(x + (k & 1 ? s : 0)), Real(y + (k & 2 ? s : 0)), Real(z + (k & 4 ? s : 0))});
    for (const std::uint32_t k : {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                  2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5})
      boxes.push_back(base + k);
  }
  mesh.surfaces.push_back({kSolid, terrain});
  mesh.surfaces.push_back({kSolid, boxes});
  return mesh;
}

/// FNV-1a of the model's .cm text.
std::uint64_t modelHash(const TriangleMesh& mesh) {
  auto built = buildCollisionModelFromTriangles(mesh, "golden", goldenMaterials());
  EXPECT_TRUE(built) << built.error().toString();
  if (!built) return 0;
  const std::string text = writeCmText(std::span<const ModelPtr>(&built->model, 1), 0);
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ull;
  return h;
}

TEST(MeshBuildGolden, OneSidedTerrainAndBoxesMerge) {
  if (sizeof(Real) != sizeof(float)) GTEST_SKIP() << "the hashes are of float (not CMKIT_DOUBLE) builds";
  EXPECT_EQ(modelHash(goldenMesh(1, 24, 60)), 5498513259998152012ull);
}

TEST(MeshBuildGolden, TwoSided) {
  if (sizeof(Real) != sizeof(float)) GTEST_SKIP() << "the hashes are of float (not CMKIT_DOUBLE) builds";
  TriangleMesh mesh = goldenMesh(2, 24, 60);
  for (MeshSurface& s : mesh.surfaces) s.material = kTwoSided;
  EXPECT_EQ(modelHash(mesh), 10747877414356187874ull);
}

TEST(MeshBuildGolden, MixedMaterialsAndDeepTree) {
  if (sizeof(Real) != sizeof(float)) GTEST_SKIP() << "the hashes are of float (not CMKIT_DOUBLE) builds";
  TriangleMesh mesh = goldenMesh(3, 40, 400);
  mesh.surfaces[1].material = kClip;
  EXPECT_EQ(modelHash(mesh), 5655712335165684507ull);
}

/// `count` two-sided triangles apart from each other, all within 60 units
/// (a node smaller than kMinNodeSize is split only when it holds more than
/// kMaxNodePolygons polygons).
TriangleMesh smallTwoSidedMesh(int count) {
  TriangleMesh mesh;
  std::vector<std::uint32_t> indices;
  for (int i = 0; i < count; ++i) {
    const Real x = Real(i % 8 * 7), y = Real(i / 8 % 8 * 7), z = Real(i / 64 * 7);
    const auto base = std::uint32_t(mesh.positions.size());
    mesh.positions.push_back({x, y, z});
    mesh.positions.push_back({x + 3, y, z + 1});
    mesh.positions.push_back({x, y + 3, z + 2});
    indices.insert(indices.end(), {base, base + 1, base + 2});
  }
  mesh.surfaces.push_back({kTwoSided, indices});
  return mesh;
}

// The tree is grown with each two-sided polygon and its reversed copy as one
// entry (axial_tree.cpp): the small node's polygon count still counts both.
TEST(MeshBuildGolden, SmallNodeCountsBothSidesOfTwoSidedPolygons) {
  static_assert(tol::kMaxNodePolygons == 128);
  auto nodesOf = [](int count) {
    auto built = buildCollisionModelFromTriangles(smallTwoSidedMesh(count), "small", goldenMaterials());
    EXPECT_TRUE(built) << built.error().toString();
    return built ? built->model->nodes().size() : 0;
  };
  EXPECT_EQ(nodesOf(64), 1u);  // 128 polygons: not split
  EXPECT_GT(nodesOf(65), 1u);  // 130: split
}

}  // namespace
}  // namespace cmkit
