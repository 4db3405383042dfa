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
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
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

/// A player-clip brush (y <= 0) and a monster-clip brush (y >= 0) back to
/// back at y = 0 with the same x and z extents, so their y = 0 faces and
/// every line of those faces coincide (as primitives 7 and 8 of
/// synthetic/water_clip.map), on a floor far below.
ModelPtr backToBackClips(bool robust) {
  const std::string text = "Version 2\n{\n\"classname\" \"worldspawn\"\n" +
                           box("textures/common/player_clip", {0, -512, 0}, {16, 0, 128}) +
                           box("textures/common/monster_clip", {0, 0, 0}, {16, 256, 128}) +
                           box("textures/base_wall/lfwall27d", {-528, -528, -16}, {528, 528, 0}) + "}\n";
  auto map = parseMapText(text);
  EXPECT_TRUE(map.ok()) << (map.ok() ? "" : map.error().toString());
  if (!map) return nullptr;
  BuildOptions options;
  options.robustEdges = robust;
  auto built = buildCollisionModels(*map, MaterialTable{}, options);
  EXPECT_TRUE(built.ok());
  if (!built || built->models.empty()) return nullptr;
  return built->models[0];
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
