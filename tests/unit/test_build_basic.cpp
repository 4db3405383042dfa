// Map -> collision model builder on small hand-made maps: a cube, touching
// cubes (contained faces removed, coplanar faces merged), a room big enough
// for a BSP tree, patches, naming, contents rules, vertex welding across
// hash cells, and the original's particular behaviours.
#include <gtest/gtest.h>

#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"

namespace {

using namespace cmkit;

/// One brushDef3 side "( a b c d ) ( ( ... ) ) material": plane n.p = dist.
std::string side(float nx, float ny, float nz, float dist, const std::string& material = "textures/a") {
  char buf[256];
  std::snprintf(buf, sizeof buf, "( %g %g %g %g ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"%s\" 0 0 0\n", nx,
                ny, nz, -dist, material.c_str());
  return buf;
}

/// An axis-aligned box brush; `materials` gives the six sides' materials
/// (+z, +y, +x, -z, -y, -x).
std::string box(Vec3 mn, Vec3 mx, std::vector<std::string> materials = {}) {
  if (materials.empty()) materials.assign(6, "textures/a");
  return "{\nbrushDef3\n{\n" + side(0, 0, 1, mx.z, materials[0]) + side(0, 1, 0, mx.y, materials[1]) +
         side(1, 0, 0, mx.x, materials[2]) + side(0, 0, -1, -mn.z, materials[3]) +
         side(0, -1, 0, -mn.y, materials[4]) + side(-1, 0, 0, -mn.x, materials[5]) + "}\n}\n";
}

std::string entity(const std::string& keys, const std::string& primitives) {
  return "{\n" + keys + primitives + "}\n";
}

std::string world(const std::string& primitives) {
  return entity("\"classname\" \"worldspawn\"\n", primitives);
}

struct Built {
  std::vector<ModelPtr> models;
  std::vector<std::string> warnings;
};

Built buildText(const std::string& body) {
  auto map = parseMapText("Version 2\n" + body, "test.map");
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  Built b;
  if (!map.ok()) return b;
  MaterialTable materials;
  auto built = buildCollisionModels(*map, materials);
  EXPECT_TRUE(built.ok());
  if (built.ok()) {
    b.models = built->models;
    b.warnings = built->warnings;
  }
  return b;
}

/// Structural invariants every built model satisfies.
void checkInvariants(const CollisionModel& m) {
  ASSERT_FALSE(m.nodes().empty());
  std::set<int> referencedPolygons;
  std::set<int> referencedBrushes;
  for (std::size_t i = 0; i < m.nodes().size(); ++i) {
    const CmNode& n = m.nodes()[i];
    if (!n.isLeaf()) {
      ASSERT_GT(n.children[0], static_cast<int>(i));  // pre-order
      ASSERT_GT(n.children[1], n.children[0]);        // front child first
      EXPECT_EQ(m.nodes()[static_cast<std::size_t>(n.children[0])].parent, static_cast<int>(i));
      EXPECT_EQ(m.nodes()[static_cast<std::size_t>(n.children[1])].parent, static_cast<int>(i));
    }
    for (const int p : m.polygonsAt(n)) referencedPolygons.insert(p);
    for (const int b : m.brushesAt(n)) referencedBrushes.insert(b);
  }
  EXPECT_EQ(referencedPolygons.size(), m.polygons().size());
  EXPECT_EQ(referencedBrushes.size(), m.brushes().size());
  for (const CmPolygon& p : m.polygons()) {
    ASSERT_GE(p.numEdges, 3u);
    // consecutive edges are connected
    const auto edges = m.edgesOf(p);
    for (std::size_t i = 0; i < edges.size(); ++i) {
      const std::int32_t e = edges[i];
      const std::int32_t next = edges[(i + 1) % edges.size()];
      ASSERT_NE(e, 0);
      const CmEdge& ce = m.edges()[static_cast<std::size_t>(std::abs(e))];
      const int end = e > 0 ? ce.vertex[1] : ce.vertex[0];
      EXPECT_EQ(end, m.edgeStart(next));
    }
  }
}

TEST(BuildBasic, SingleCube) {
  const Built b = buildText(world(box({-64, -64, -64}, {64, 64, 64})));
  ASSERT_EQ(b.models.size(), 1u);
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.name(), "worldMap");
  EXPECT_EQ(m.vertices().size(), 8u);
  EXPECT_EQ(m.numEdges(), 12u);
  EXPECT_EQ(m.edges().size(), 13u);  // with the dummy edge 0
  EXPECT_EQ(m.polygons().size(), 6u);
  EXPECT_EQ(m.brushes().size(), 1u);
  EXPECT_EQ(m.nodes().size(), 1u);
  EXPECT_TRUE(m.nodes()[0].isLeaf());
  EXPECT_EQ(m.polygonRefs().size(), 6u);
  EXPECT_EQ(m.contents(), 3u);  // solid | opaque
  EXPECT_EQ(m.bounds(), Bounds({-64, -64, -64}, {64, 64, 64}));
  for (std::size_t e = 1; e < m.edges().size(); ++e) {
    EXPECT_EQ(m.edges()[e].numUsers, 2);
    EXPECT_FALSE(m.edges()[e].internal);
  }
  // Node lists are prepended: the last side's polygon comes first.
  EXPECT_EQ(m.polygons()[0].plane.normal, Vec3(-1, 0, 0));
  EXPECT_EQ(m.polygons()[5].plane.normal, Vec3(0, 0, 1));
  EXPECT_EQ(m.polygons()[5].plane.dist, 64);
  ASSERT_EQ(m.materials().size(), 1u);
  EXPECT_EQ(m.materials()[0], "textures/a");
  EXPECT_EQ(m.stats().internalEdges, 0);
  EXPECT_EQ(m.stats().sharpEdges, 0);
  checkInvariants(m);
  EXPECT_TRUE(b.warnings.empty());
}

TEST(BuildBasic, TouchingCubesLoseSharedFacesAndMerge) {
  const Built b = buildText(world(box({-64, -64, -64}, {64, 64, 64}) + box({64, -64, -64}, {192, 64, 64})));
  ASSERT_EQ(b.models.size(), 1u);
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.brushes().size(), 2u);
  // the two faces at x = 64 are inside the other cube
  EXPECT_EQ(m.stats().containedPolygonsRemoved, 2);
  // top, bottom, front and back halves merge (collinear edges joined)
  EXPECT_EQ(m.stats().polygonsMerged, 4);
  EXPECT_EQ(m.polygons().size(), 6u);
  for (const CmPolygon& p : m.polygons()) EXPECT_EQ(p.numEdges, 4u);
  // vertices of the dropped middle edges survive (compaction keeps every
  // vertex of an edge slot, used or not), as in the original
  EXPECT_EQ(m.vertices().size(), 12u);
  EXPECT_EQ(m.numEdges(), 12u);
  EXPECT_EQ(m.bounds(), Bounds({-64, -64, -64}, {192, 64, 64}));
  checkInvariants(m);
}

TEST(BuildBasic, CoplanarTouchingFacesFacingTheSameWaySurvive) {
  // A thin slab lying on the top face of a cube: the cube's top face is on
  // the slab's bottom plane (opposite facing: removed where covered), the
  // slab's top is above. Different contents never chop each other.
  const Built b =
      buildText(world(box({0, 0, 0}, {64, 64, 64}) +
                      box({0, 0, 64}, {64, 64, 72}, std::vector<std::string>(6, "textures/water"))));
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.stats().containedPolygonsRemoved, 0);
  EXPECT_EQ(m.polygons().size(), 12u);
  EXPECT_EQ(m.contents(), 3u | 4u);
  checkInvariants(m);
}

TEST(BuildBasic, RoomGetsBspTree) {
  // six walls of a 1024 x 1024 x 256 room
  const std::string walls = box({-512, -512, -16}, {512, 512, 0}) + box({-512, -512, 256}, {512, 512, 272}) +
                            box({-528, -512, 0}, {-512, 512, 256}) + box({512, -512, 0}, {528, 512, 256}) +
                            box({-512, -528, 0}, {512, -512, 256}) + box({-512, 512, 0}, {512, 528, 256}) +
                            box({-64, -64, 0}, {64, 64, 128});
  const Built b = buildText(world(walls));
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.brushes().size(), 7u);
  EXPECT_GT(m.nodes().size(), 1u);
  EXPECT_FALSE(m.nodes()[0].isLeaf());
  EXPECT_GT(m.stats().internalEdges, 0);
  EXPECT_GT(m.stats().containedPolygonsRemoved, 0);
  checkInvariants(m);
  // every leaf's polygons touch the leaf's region: walk down from the root
  // and check that split planes separate children
  for (const CmNode& n : m.nodes()) {
    if (n.isLeaf()) continue;
    for (const int p : m.polygonsAt(m.nodes()[static_cast<std::size_t>(n.children[0])])) {
      EXPECT_GE(m.polygons()[static_cast<std::size_t>(p)].bounds.max[n.planeType], n.planeDist);
    }
    for (const int p : m.polygonsAt(m.nodes()[static_cast<std::size_t>(n.children[1])])) {
      EXPECT_LE(m.polygons()[static_cast<std::size_t>(p)].bounds.min[n.planeType], n.planeDist);
    }
  }
}

TEST(BuildBasic, FourBrushesGetNoTreeFiveMayGetOne) {
  std::string four;
  for (int i = 0; i < 4; ++i) four += box({i * 256.0f, 0, 0}, {i * 256.0f + 64, 64, 64});
  const Built b4 = buildText(world(four));
  EXPECT_EQ(b4.models[0]->nodes().size(), 1u);
  const Built b5 = buildText(world(four + box({1024, 0, 0}, {1088, 64, 64})));
  EXPECT_GT(b5.models[0]->nodes().size(), 1u);
}

TEST(BuildBasic, FlatPatchIsOneQuad) {
  const std::string patch =
      "{\npatchDef2\n{\n\"textures/a\"\n( 3 3 0 0 0 )\n(\n"
      "( ( 0 0 0 0 0 ) ( 0 64 0 0 0 ) ( 0 128 0 0 0 ) )\n"
      "( ( 64 0 0 0 0 ) ( 64 64 0 0 0 ) ( 64 128 0 0 0 ) )\n"
      "( ( 128 0 0 0 0 ) ( 128 64 0 0 0 ) ( 128 128 0 0 0 ) )\n"
      ")\n}\n}\n";
  const Built b = buildText(world(patch));
  ASSERT_EQ(b.models.size(), 1u);
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.brushes().size(), 0u);
  ASSERT_EQ(m.polygons().size(), 1u);
  EXPECT_EQ(m.polygons()[0].numEdges, 4u);
  EXPECT_EQ(std::fabs(m.polygons()[0].plane.normal.z), 1.0f);
  checkInvariants(m);
}

TEST(BuildBasic, CurvedPatchMakesManyPolygons) {
  const std::string patch =
      "{\npatchDef2\n{\n\"textures/a\"\n( 3 3 0 0 0 )\n(\n"
      "( ( 0 0 0 0 0 ) ( 0 128 0 0 0 ) ( 0 256 0 0 0 ) )\n"
      "( ( 128 0 256 0 0 ) ( 128 128 256 0 0 ) ( 128 256 256 0 0 ) )\n"
      "( ( 256 0 0 0 0 ) ( 256 128 0 0 0 ) ( 256 256 0 0 0 ) )\n"
      ")\n}\n}\n";
  const Built b = buildText(world(patch));
  const CollisionModel& m = *b.models[0];
  EXPECT_GT(m.polygons().size(), 4u);
  // all patch cells are planar quads here (the curve is along one axis)
  for (const CmPolygon& p : m.polygons()) EXPECT_EQ(p.numEdges, 4u);
  // neighbouring cells share edges, some of them internal (concave side)
  checkInvariants(m);
}

TEST(BuildBasic, ModelNames) {
  const std::string cube = box({0, 0, 0}, {16, 16, 16});
  const Built b =
      buildText(world(cube) + entity("\"classname\" \"func_static\"\n\"name\" \"door\"\n", cube) +
                entity("\"classname\" \"func_static\"\n\"model\" \"lift\"\n\"name\" \"x\"\n", cube) +
                entity("\"classname\" \"func_static\"\n", cube) +
                entity("\"classname\" \"func_static\"\n\"model\" \"models/a.lwo\"\n", "") +
                entity("\"classname\" \"func_static\"\n", cube));
  ASSERT_EQ(b.models.size(), 5u);  // the entity that only names a mesh gets none
  EXPECT_EQ(b.models[0]->name(), "worldMap");
  EXPECT_EQ(b.models[1]->name(), "door");
  EXPECT_EQ(b.models[2]->name(), "lift");
  EXPECT_EQ(b.models[3]->name(), "unnamed inline model");
  EXPECT_EQ(b.models[4]->name(), "unnamed inline model");
}

TEST(BuildBasic, FirstModelIsWorldMapEvenWhenNotTheWorldspawn) {
  const std::string cube = box({0, 0, 0}, {16, 16, 16});
  const Built b = buildText(world("") + entity("\"classname\" \"func_static\"\n", cube));
  ASSERT_EQ(b.models.size(), 1u);
  EXPECT_EQ(b.models[0]->name(), "worldMap");
}

TEST(BuildBasic, PrimitivesWithoutContentsGiveAnEmptyModel) {
  const Built b =
      buildText(world(box({0, 0, 0}, {16, 16, 16})) +
                entity("\"classname\" \"func_static\"\n\"name\" \"ghost\"\n",
                       box({0, 0, 0}, {16, 16, 16}, std::vector<std::string>(6, "textures/common/noclip"))));
  ASSERT_EQ(b.models.size(), 2u);
  const CollisionModel& m = *b.models[1];
  EXPECT_EQ(m.name(), "ghost");
  EXPECT_EQ(m.polygons().size(), 0u);
  EXPECT_EQ(m.brushes().size(), 0u);
  EXPECT_EQ(m.vertices().size(), 0u);
  EXPECT_EQ(m.edges().size(), 0u);
  EXPECT_EQ(m.nodes().size(), 1u);
  EXPECT_EQ(m.bounds(), Bounds(Vec3{}, Vec3{}));
  EXPECT_EQ(m.contents(), 0u);
}

TEST(BuildBasic, BrushContentsIgnoreTheLastSide) {
  // Only the last side (-x) has contents: no brush, but that side's polygon.
  std::vector<std::string> mats(6, "textures/common/noclip");
  mats[5] = "textures/a";
  const Built b = buildText(world(box({0, 0, 0}, {16, 16, 16}, mats)));
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.brushes().size(), 0u);
  ASSERT_EQ(m.polygons().size(), 1u);
  EXPECT_EQ(m.polygons()[0].plane.normal, Vec3(-1, 0, 0));

  // Contents are the OR of sides 0..n-2; the material is side n-2's.
  std::vector<std::string> mixed(6, "textures/a");
  mixed[0] = "textures/common/player_clip";   // +z
  mixed[4] = "textures/b";                    // -y, side n-2
  mixed[5] = "textures/common/monster_clip";  // -x, the last side: ignored
  const Built b2 = buildText(world(box({0, 0, 0}, {16, 16, 16}, mixed)));
  const CollisionModel& m2 = *b2.models[0];
  ASSERT_EQ(m2.brushes().size(), 1u);
  EXPECT_EQ(m2.brushes()[0].contents, 3u | 8u);
  EXPECT_EQ(m2.materialName(m2.brushes()[0].material), "textures/b");
  EXPECT_EQ(m2.contents(), 3u | 8u | 16u);  // the -x polygon is monster clip
}

TEST(BuildBasic, VerticesWeldAcrossHashCells) {
  // Vertices 0.05 apart on both sides of a 4-unit hash cell border (in x
  // only, then in x and y): the original's one-cell lookup misses them;
  // cmkit finds them (dhewm3's neighbour-cell search).
  const Built one = buildText(world(box({0, 0, 0}, {5.6f, 16, 16}) + box({5.65f, 0, 0}, {16, 16, 16})));
  EXPECT_EQ(one.models[0]->vertices().size(), 12u);
  const Built two = buildText(world(box({0, 0, 0}, {5.6f, 5.6f, 16}) + box({5.65f, 5.65f, 0}, {16, 16, 16})));
  EXPECT_EQ(two.models[0]->vertices().size(), 14u);
}

TEST(BuildBasic, PatchPolygonsAreFilteredIntoTheBrushTree) {
  std::string walls;
  for (int i = 0; i < 6; ++i) walls += box({i * 256.0f, 0, 0}, {i * 256.0f + 64, 64, 64});
  const std::string patch =
      "{\npatchDef2\n{\n\"textures/a\"\n( 3 3 0 0 0 )\n(\n"
      "( ( 0 0 200 0 0 ) ( 0 64 200 0 0 ) ( 0 128 200 0 0 ) )\n"
      "( ( 640 0 200 0 0 ) ( 640 64 200 0 0 ) ( 640 128 200 0 0 ) )\n"
      "( ( 1280 0 200 0 0 ) ( 1280 64 200 0 0 ) ( 1280 128 200 0 0 ) )\n"
      ")\n}\n}\n";
  const Built b = buildText(world(walls + patch));
  const CollisionModel& m = *b.models[0];
  EXPECT_GT(m.nodes().size(), 1u);
  EXPECT_EQ(m.polygons().size(), 6u * 6u + 1u);
  checkInvariants(m);
}

// ---- bad input: never a crash, warnings instead -------------------------

TEST(BuildBadInput, BrushesWithTooFewSides) {
  const std::string three =
      "{\nbrushDef3\n{\n" + side(0, 0, 1, 16) + side(0, 0, -1, 0) + side(1, 0, 0, 16) + "}\n}\n";
  const std::string one = "{\nbrushDef3\n{\n" + side(0, 0, 1, 16) + "}\n}\n";
  const std::string none = "{\nbrushDef3\n{\n}\n}\n";
  // (the cube lies outside the open brush's half-spaces: the open brush has
  // contents and huge bounds, so it would chop anything inside it)
  const Built b = buildText(world(three + one + none + box({100, 0, 0}, {116, 16, 16})));
  ASSERT_EQ(b.models.size(), 1u);
  EXPECT_FALSE(b.warnings.empty());
  const CollisionModel& m = *b.models[0];
  // the open brushes' polygons reach the world limit and are dropped (with a
  // warning each); the cube survives
  EXPECT_EQ(m.polygons().size(), 6u);
  EXPECT_EQ(m.brushes().size(), 2u);  // the open 3-sided brush and the cube
  checkInvariants(m);
}

TEST(BuildBadInput, DuplicatePlanes) {
  const std::string dup = "{\nbrushDef3\n{\n" + side(0, 0, 1, 16) + side(0, 0, 1, 16) + side(0, 1, 0, 16) +
                          side(1, 0, 0, 16) + side(0, 0, -1, 0) + side(0, -1, 0, 0) + side(-1, 0, 0, 0) +
                          "}\n}\n";
  const Built b = buildText(world(dup));
  const CollisionModel& m = *b.models[0];
  // each duplicate clips the other away (ClipInPlace keeps nothing on the
  // plane): the top face is lost, as in the original
  EXPECT_EQ(m.brushes().size(), 1u);
  EXPECT_EQ(m.polygons().size(), 5u);
  checkInvariants(m);
}

TEST(BuildBadInput, InvertedBrushIsEmptyAndMakesInfiniteModelBounds) {
  // max < min: the planes enclose nothing. The original keeps the brush
  // with cleared bounds, which makes the model bounds +-1e30.
  const std::string inverted = "{\nbrushDef3\n{\n" + side(0, 0, 1, 0) + side(0, 1, 0, 0) + side(1, 0, 0, 0) +
                               side(0, 0, -1, -16) + side(0, -1, 0, -16) + side(-1, 0, 0, -16) + "}\n}\n";
  const Built b = buildText(world(inverted));
  const CollisionModel& m = *b.models[0];
  EXPECT_EQ(m.polygons().size(), 0u);
  ASSERT_EQ(m.brushes().size(), 1u);
  EXPECT_TRUE(m.brushes()[0].bounds.isCleared());
  EXPECT_EQ(m.bounds().min.x, -tol::kBoundsInfinity);
  EXPECT_EQ(m.bounds().max.x, tol::kBoundsInfinity);
  EXPECT_FALSE(b.warnings.empty());
}

TEST(BuildBadInput, HugeCoordinatesAreDroppedWithAWarning) {
  const Built b = buildText(world(box({0, 0, 0}, {200000, 16, 16})));
  const CollisionModel& m = *b.models[0];
  EXPECT_FALSE(b.warnings.empty());
  EXPECT_LT(m.polygons().size(), 6u);
}

// Found by fuzzing: a patch point at 6.5e13 makes welded vertices whose
// polygon outlines (built directly or by merging) do not close in the
// original; cmkit drops or does not merge them, so every outline is a loop.
TEST(BuildBadInput, EnormousPatchPointsStillGiveClosedOutlines) {
  const std::string patch =
      "{\npatchDef2\n{\n\"textures/a\"\n( 3 3 0 0 0 )\n(\n"
      "( ( 0 0 0 0 0 ) ( 0 0 32 0 0.5 ) ( 0 0 64 0 1 ) )\n"
      "( ( 64 0 0 0.5 0 ) ( 64 0 32 0.5 0.5 ) ( 64 0 64 0.5 1 ) )\n"
      "( ( 64 64 0 1 0 ) ( 64 64 32 1 0.5 ) ( 64 64 64999999999999 1 1 ) )\n)\n}\n}\n";
  const Built b = buildText(world(box({-512, -512, -16}, {512, 512, 0})) +
                            entity("\"classname\" \"func_static\"\n", patch));
  ASSERT_EQ(b.models.size(), 2u);
  for (const ModelPtr& m : b.models) checkInvariants(*m);
  // In float the patch keeps some polygons; in double the welded vertices
  // differ and every winding may reach beyond kMaxWorldCoord and be dropped.
  if constexpr (!kDoublePrecision) {
    EXPECT_GT(b.models[1]->polygons().size(), 0u);
  }
  // Hundreds of dropped polygons give one line per message, with a count.
  const std::set<std::string> distinct(b.warnings.begin(), b.warnings.end());
  EXPECT_EQ(distinct.size(), b.warnings.size());
  EXPECT_LE(b.warnings.size(), 3u);
  bool counted = false;
  for (const std::string& w : b.warnings)
    counted |= w.find("reaches the world limit; dropped (") != std::string::npos;
  EXPECT_TRUE(counted) << (b.warnings.empty() ? "" : b.warnings.front());
}

TEST(BuildBadInput, ProgressIsReported) {
  auto map = parseMapText("Version 2\n" + world(box({0, 0, 0}, {16, 16, 16})) + entity("\"a\" \"b\"\n", ""),
                          "p.map");
  ASSERT_TRUE(map.ok());
  std::vector<std::pair<std::size_t, std::size_t>> calls;
  BuildOptions options;
  options.progress = [&](std::size_t done, std::size_t total) { calls.emplace_back(done, total); };
  auto models = buildCollisionModels(*map, MaterialTable{}, options);
  ASSERT_TRUE(models.ok());
  ASSERT_EQ(calls.size(), 2u);
  EXPECT_EQ(calls.back(), std::make_pair(std::size_t(2), std::size_t(2)));
}

}  // namespace
