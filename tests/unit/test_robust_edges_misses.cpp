// Missed collisions with robust edges that `cmkit soak` found (issue #34,
// item 1): a brush face doubled by a coplanar face of another brush of
// different contents, back to back (a player-clip brush against a
// monster-clip brush, synthetic/water_clip.map), where turned and unturned
// trace models crossing the face at a two-edge corner ended inside the
// player-clip brush. The robust edge-normal rule (TwoSidedSheets) took the
// two back-to-back faces for a two-sided sheet and chose the monster-clip
// face's side for the normal of the corner lines, so their epsilon edges lay
// inside the player-clip brush and the edge tests rejected every contact
// there. Twins now need the same material and contents (edge_normals.cpp).
// And point traces across the seam of coplanar brush faces that meet at a
// T-junction (issue #34's internal-edge point traces): they passed between
// the polygons into the brushes; robust edges now cut the polygons there
// (t_junctions.cpp).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/query.h"
#include "cmkit/trace_model.h"
#include "test_support.h"

using namespace cmkit;

namespace {

/// The soak's mask: solid | playerclip | body.
constexpr std::uint32_t kMask = contents::kMaskPlayerSolid;

std::string box(const char* material, const Vec3& lo, const Vec3& hi) {
  auto face = [&](const char* n, Real d) {
    return "  ( " + std::string(n) + " " + std::to_string(d) +
           " ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"" + material + "\" 0 0 0\n";
  };
  return "{\n brushDef3\n {\n" + face("0 0 1", -hi.z) + face("0 0 -1", lo.z) + face("1 0 0", -hi.x) +
         face("-1 0 0", lo.x) + face("0 1 0", -hi.y) + face("0 -1 0", lo.y) + " }\n}\n";
}

/// A brush of `material`: the prism over the convex polygon `xy`
/// (counter-clockwise) from z0 to z1, its planes written to 9 significant
/// digits, as an editor writes them.
std::string prism(const char* material, const std::vector<std::array<double, 2>>& xy, double z0, double z1) {
  std::string out = "{\n brushDef3\n {\n";
  auto plane = [&](double nx, double ny, double nz, double d) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "  ( %.9g %.9g %.9g %.9g ) ( ( 0.0078125 0 0 ) ( 0 0.0078125 0 ) ) \"%s\" 0 0 0\n",
                  double(float(nx)), double(float(ny)), double(float(nz)), double(float(d)), material);
    out += line;
  };
  plane(0, 0, 1, -z1);
  plane(0, 0, -1, z0);
  for (std::size_t i = 0; i < xy.size(); ++i) {
    const auto& a = xy[i];
    const auto& b = xy[(i + 1) % xy.size()];
    const double ex = b[0] - a[0], ey = b[1] - a[1], len = std::hypot(ex, ey);
    const double nx = ey / len, ny = -ex / len;
    plane(nx, ny, 0, -(nx * a[0] + ny * a[1]));
  }
  return out + " }\n}\n";
}

/// The world model of a map of `brushes` (worldspawn), with or without
/// robust edges.
ModelPtr buildWorld(const std::string& brushes, bool robust) {
  auto map = parseMapText("Version 2\n{\n\"classname\" \"worldspawn\"\n" + brushes + "}\n");
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return nullptr;
  BuildOptions options;
  options.robustEdges = robust;
  auto built = buildCollisionModels(*map, MaterialTable{}, options);
  EXPECT_TRUE(built.ok());
  if (!built || built->models.empty()) return nullptr;
  return built->models[0];
}

/// A player-clip brush (y <= 0) and a monster-clip brush (y >= 0) back to
/// back at y = 0 with the same x and z extents, so their y = 0 faces and
/// every line of those faces coincide (as primitives 7 and 8 of
/// synthetic/water_clip.map), on a floor far below.
ModelPtr backToBackClips(bool robust) {
  return buildWorld(box("textures/common/player_clip", {0, -512, 0}, {16, 0, 128}) +
                        box("textures/common/monster_clip", {0, 0, 0}, {16, 256, 128}) +
                        box("textures/base_wall/lfwall27d", {-528, -528, -16}, {528, 528, 0}),
                    robust);
}

TraceResult sweep(const CollisionModel& m, const TraceModel& trm, const Mat3& axis, const Vec3& from,
                  const Vec3& to, QueryWork& work) {
  TranslationQuery q;
  q.trm = &trm;
  q.trmAxis = axis;
  q.start = from;
  q.end = to;
  q.contentMask = kMask;
  return translate(m, q, work);
}

bool overlapsSolid(const CollisionModel& m, const TraceModel& trm, const Mat3& axis, const Vec3& at,
                   QueryWork& work) {
  ContentsQuery q;
  q.trm = &trm;
  q.trmAxis = axis;
  q.position = at;
  q.contentMask = kMask;
  return (contentsTest(m, q, work).contents & kMask) != 0;
}

/// A uniformly random rotation (rotationFromUniforms).
Mat3 randomRotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const double u1 = u(rng), u2 = u(rng), u3 = u(rng);
  return rotationFromUniforms(u1, u2, u3);
}

}  // namespace

// The soak's case (water_clip.map, seed 1): a polygon volume moving down -y
// across the doubled face meets the corner line x = 0, y = 0 first. With the
// sheet rule's normal the robust build ran on to the x = 16 line and ended
// 16.25 units inside the player clip; now both builds stop at the first
// corner, with the same answer.
TEST(RobustEdgesMisses, BackToBackClipFacesSoakCase) {
  const ModelPtr robust = backToBackClips(true);
  const ModelPtr original = backToBackClips(false);
  ASSERT_TRUE(robust && original);
  auto trm = TraceModel::parse("polygonvolume:8:-16,-16,8;16,-16,8;16,16,8;-16,16,8");
  ASSERT_TRUE(trm.ok());
  QueryWork work;
  const Vec3 from{27.1333f, 54.733154f, 62.515087f}, to{-97.08977f, -216.39816f, 49.9062f};
  ASSERT_FALSE(overlapsSolid(*robust, *trm, Mat3{}, from, work));
  const TraceResult r = sweep(*robust, *trm, Mat3{}, from, to, work);
  const TraceResult o = sweep(*original, *trm, Mat3{}, from, to, work);
  EXPECT_LT(r.fraction, 1);
  EXPECT_FALSE(overlapsSolid(*robust, *trm, Mat3{}, r.endPos, work))
      << "fraction " << r.fraction << " end " << r.endPos.x << "," << r.endPos.y << "," << r.endPos.z;
  EXPECT_EQ(r.fraction, o.fraction);
  EXPECT_EQ(r.contact.normal, o.contact.normal);
}

// Turned convex shapes (the soak's kinds) from random free starts on the
// monster-clip side to random ends past the player clip's far side: every
// move must stop outside the player clip, with robust edges as without.
// (The soak's misses on water_clip.map before the fix were of this kind:
// turned cylinders, boxes and bones as well as unturned shapes.)
TEST(RobustEdgesMisses, TurnedShapesAcrossBackToBackClipFaces) {
  const char* const kinds[] = {
      "box:-16,-16,0,16,16,72",          "cylinder:8:-16,-16,0,16,16,72",     "cone:6:-12,-12,0,12,12,40",
      "octahedron:-16,-16,-16,16,16,16", "dodecahedron:-16,-16,-16,16,16,16", "bone:48,12"};
  std::vector<TraceModel> trms;
  for (const char* k : kinds) {
    auto t = TraceModel::parse(k);
    ASSERT_TRUE(t.ok()) << k;
    trms.push_back(*t);
  }
  for (const bool robust : {true, false}) {
    const ModelPtr m = backToBackClips(robust);
    ASSERT_TRUE(m);
    std::mt19937 rng(34);
    std::uniform_real_distribution<Real> x(-40, 56), yStart(60, 140), yEnd(-140, -20), z(30, 100);
    QueryWork work;
    int run = 0, embedded = 0;
    for (int i = 0; i < 2000; ++i) {
      const TraceModel& trm = trms[std::size_t(i) % trms.size()];
      const Mat3 axis = randomRotation(rng);
      const Vec3 from{x(rng), yStart(rng), z(rng)}, to{x(rng), yEnd(rng), z(rng)};
      if (overlapsSolid(*m, trm, axis, from, work)) continue;
      ++run;
      const TraceResult r = sweep(*m, trm, axis, from, to, work);
      embedded += overlapsSolid(*m, trm, axis, r.endPos, work);
    }
    EXPECT_GT(run, 1000);
    EXPECT_EQ(embedded, 0) << (robust ? "robust" : "original") << " edges, " << run << " sweeps";
  }
}

// ---- T-junctions of coplanar faces -----------------------------------------

namespace {

using XY = std::array<double, 2>;

/// Brushes 64 high whose tops (z = 64) are coplanar and meet along seams,
/// on a floor far below; `seams` are the lines (in the top plane) where two
/// tops meet, all inside the union of the tops.
struct SeamMap {
  const char* name;
  std::string brushes;
  std::vector<std::array<XY, 2>> seams;
};

std::string floorFarBelow() {
  return prism("textures/floor", {{-512, -512}, {640, -512}, {640, 640}, {-512, 640}}, -600, -584);
}

/// Brush a: the triangle (0,0), (96,0), (96,96); the other half of the
/// square split at (32,32), a point of a's diagonal: b (0,0), (32,32),
/// (0,96) and c (32,32), (96,96), (0,96). Different materials: no merge.
std::string diagonalTJunction() {
  return prism("textures/a", {{0, 0}, {96, 0}, {96, 96}}, 0, 64) +
         prism("textures/b", {{0, 0}, {32, 32}, {0, 96}}, 0, 64) +
         prism("textures/c", {{32, 32}, {96, 96}, {0, 96}}, 0, 64) + floorFarBelow();
}

/// As diagonalTJunction on the diagonal (0,0)-(100,37), split at
/// (30, 11.1): welding snaps that vertex to (30, 11.1015625), 0.0015 units
/// off a's edge, which leaves a sliver between the tops.
std::string weldedTJunction() {
  return prism("textures/a", {{0, 0}, {100, 0}, {100, 37}}, 0, 64) +
         prism("textures/b", {{0, 0}, {30, 11.1}, {0, 37}}, 0, 64) +
         prism("textures/c", {{30, 11.1}, {100, 37}, {0, 37}}, 0, 64) + floorFarBelow();
}

std::vector<SeamMap> seamMaps() {
  auto rect = [](double x0, double y0, double x1, double y1) {
    return std::vector<XY>{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  };
  std::vector<SeamMap> maps;
  maps.push_back({"side by side",
                  prism("textures/a", rect(0, 0, 64, 64), 0, 64) +
                      prism("textures/b", rect(64, 0, 128, 64), 0, 64) + floorFarBelow(),
                  {{XY{64, 0}, XY{64, 64}}}});
  maps.push_back({"one against two",
                  prism("textures/a", rect(0, 0, 64, 64), 0, 64) +
                      prism("textures/b", rect(64, 0, 128, 32), 0, 64) +
                      prism("textures/c", rect(64, 32, 128, 64), 0, 64) + floorFarBelow(),
                  {{XY{64, 0}, XY{64, 64}}, {XY{64, 32}, XY{128, 32}}}});
  maps.push_back({"diagonal",
                  prism("textures/a", {{0, 0}, {96, 0}, {96, 96}}, 0, 64) +
                      prism("textures/b", {{0, 0}, {96, 96}, {0, 96}}, 0, 64) + floorFarBelow(),
                  {{XY{0, 0}, XY{96, 96}}}});
  maps.push_back(
      {"diagonal T-junction", diagonalTJunction(), {{XY{0, 0}, XY{96, 96}}, {XY{32, 32}, XY{0, 96}}}});
  maps.push_back(
      {"welded T-junction", weldedTJunction(), {{XY{0, 0}, XY{100, 37}}, {XY{30, 11.1}, XY{0, 37}}}});
  maps.push_back({"overlapping",
                  prism("textures/a", rect(0, 0, 64, 64), 0, 64) +
                      prism("textures/b", rect(32, 0, 128, 64), 0, 64) + floorFarBelow(),
                  {{XY{32, 0}, XY{32, 64}}, {XY{64, 0}, XY{64, 64}}}});
  maps.push_back({"chopped by a block",
                  prism("textures/a", rect(0, 0, 128, 128), 0, 64) +
                      prism("textures/c", rect(32, 32, 96, 96), 64, 128) + floorFarBelow(),
                  {{XY{32, 32}, XY{96, 32}}, {XY{0, 32}, XY{128, 32}}, {XY{32, 0}, XY{32, 128}}}});
  return maps;
}

/// A point trace `start` -> `end` and the point contents at its end.
struct PointTrace {
  TraceResult r;
  std::uint32_t atEnd = 0;
};
PointTrace tracePoint(const CollisionModel& m, const Vec3& start, const Vec3& end, QueryWork& work) {
  TranslationQuery q;
  q.start = start;
  q.end = end;
  q.contentMask = kMask;
  PointTrace t;
  t.r = translate(m, q, work);
  PointContentsQuery at;
  at.point = t.r.endPos;
  t.atEnd = pointContents(m, at, work).contents & kMask;
  return t;
}

}  // namespace

// Issue #34's point traces that ended inside a closed brush after crossing
// a model edge between a face and a coplanar polygon of another brush. Made
// here in small: the tops of three brushes meet along a's diagonal, b and c
// at a T-junction (32,32). a's diagonal and c's edge are different lines;
// their Plücker products with this path round apart, each calls the point
// outside its polygon, and it falls into the brushes (the original's crack,
// float arithmetic). Robust edges cut a at (32,32): the seam is two shared
// edges, whose one product a and c read with opposite signs.
TEST(RobustEdgesMisses, PointTraceAcrossTJunctionOnADiagonal) {
  const Vec3 start{39.015377f, 49.7434921f, 65.2161255f}, end{40.9336624f, 28.1842537f, 62.5547485f};
  QueryWork work;
  const ModelPtr robust = buildWorld(diagonalTJunction(), true);
  ASSERT_TRUE(robust);
  const PointTrace r = tracePoint(*robust, start, end, work);
  EXPECT_LT(r.r.fraction, 1);
  EXPECT_EQ(r.atEnd, 0u) << "fraction " << r.r.fraction;
  EXPECT_EQ(r.r.contact.normal, (Vec3{0, 0, 1}));
  EXPECT_FLOAT_EQ(r.r.endPos.z, 64.25f);
  if constexpr (kDoublePrecision) return;  // the original's crack is one of float rounding
  const ModelPtr original = buildWorld(diagonalTJunction(), false);
  ASSERT_TRUE(original);
  const PointTrace o = tracePoint(*original, start, end, work);
  EXPECT_EQ(o.r.fraction, 1) << "the original's edges: the point passes between the tops";
  EXPECT_NE(o.atEnd, 0u);
}

// The T-junction's vertex welded 0.0015 units off a's edge: a sliver
// between the tops that every point trace through it crosses. Robust edges
// cut a at the welded vertex. (The original's answer is pinned in the float
// build, where the sliver was measured.)
TEST(RobustEdgesMisses, PointTraceThroughAWeldedTJunction) {
  const Vec3 start{85.7608337f, 35.5007401f, 79.2730255f}, end{90.8596497f, 32.3238106f, 58.7553291f};
  QueryWork work;
  const ModelPtr robust = buildWorld(weldedTJunction(), true);
  const ModelPtr original = buildWorld(weldedTJunction(), false);
  ASSERT_TRUE(robust && original);
  const PointTrace r = tracePoint(*robust, start, end, work);
  EXPECT_LT(r.r.fraction, 1);
  EXPECT_EQ(r.atEnd, 0u) << "fraction " << r.r.fraction;
  if constexpr (kDoublePrecision) return;
  const PointTrace o = tracePoint(*original, start, end, work);
  EXPECT_EQ(o.r.fraction, 1) << "the original's edges: the point passes through the sliver";
  EXPECT_NE(o.atEnd, 0u);
}

// Point traces across every seam of the coplanar tops (brushes side by
// side, one against two, diagonal splits, T-junctions, overlapping brushes,
// a top chopped by a block standing on it): on the seam as floats, and up
// to 1e-6 .. 1e-3 units beside it, steep to 0.05 degrees from grazing. With
// robust edges every one stops on the tops; with the original's edges
// points pass the T-junctions (the test prints how many: 9 and 240 of 1500
// in the float build).
TEST(RobustEdgesMisses, PointTracesAcrossCoplanarSeams) {
  std::mt19937 rng(34);
  std::uniform_real_distribution<double> unit(0, 1);
  const double offsets[] = {0, 0, 0, 1e-6, -1e-6, 1e-5, -1e-5, 1e-4, -1e-4, 1e-3, -1e-3};
  const double elevations[] = {90, 60, 30, 10, 3, 1, 0.3, 0.1};
  QueryWork work;
  int originalMisses = 0;
  for (const SeamMap& map : seamMaps()) {
    SCOPED_TRACE(map.name);
    const ModelPtr robust = buildWorld(map.brushes, true);
    const ModelPtr original = buildWorld(map.brushes, false);
    ASSERT_TRUE(robust && original);
    int run = 0, robustMisses = 0, mapOriginalMisses = 0;
    for (int i = 0; i < 1500; ++i) {
      const auto& seam = map.seams[std::size_t(rng() % map.seams.size())];
      const double t = 0.02 + 0.96 * unit(rng);
      const double ex = seam[1][0] - seam[0][0], ey = seam[1][1] - seam[0][1], len = std::hypot(ex, ey);
      const double off = offsets[rng() % std::size(offsets)] * unit(rng);
      const double px = seam[0][0] + ex * t - ey / len * off, py = seam[0][1] + ey * t + ex / len * off;
      const double elev =
          elevations[rng() % std::size(elevations)] * (0.5 + 0.5 * unit(rng)) * 3.14159265358979 / 180;
      const double az = 2 * 3.14159265358979 * unit(rng);
      const double dx = std::cos(elev) * std::cos(az), dy = std::cos(elev) * std::sin(az),
                   dz = -std::sin(elev);
      const double s0 = 0.5 + 39.5 * unit(rng), s1 = 0.5 + 39.5 * unit(rng);
      const Vec3 start{Real(px - dx * s0), Real(py - dy * s0), Real(64 - dz * s0)};
      const Vec3 end{Real(px + dx * s1), Real(py + dy * s1), Real(64 + dz * s1)};
      PointContentsQuery at;
      at.point = start;
      if (pointContents(*robust, at, work).contents & kMask) continue;  // started inside the block
      ++run;
      const PointTrace r = tracePoint(*robust, start, end, work);
      robustMisses += r.atEnd != 0 || r.r.fraction == 1;
      const PointTrace o = tracePoint(*original, start, end, work);
      mapOriginalMisses += o.atEnd != 0 || o.r.fraction == 1;
    }
    EXPECT_GT(run, 1000);
    EXPECT_EQ(robustMisses, 0) << run << " point traces";
    originalMisses += mapOriginalMisses;
    if (mapOriginalMisses)
      std::printf("  %s: the original's edges let %d of %d through\n", map.name, mapOriginalMisses, run);
  }
  if constexpr (!kDoublePrecision) {
    EXPECT_GT(originalMisses, 0) << "the seams of these maps are the original's cracks";
  }
}
