// Contact normals oppose the motion: of a rotation's contact point along its
// arc, of a translation's trace model along its line, for free starts and
// starts in solid alike (cmkit issue #34). Properties over random queries on
// a hand-made model and on a bundled map, and the reference lines where the
// original's rotation normal opposed the motion and cmkit's once followed it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tolerances.h"
#include "cmkit/tools/query_format.h"
#include "model_fixtures.h"
#include "test_support.h"

using namespace cmkit;
using test::ModelMaker;

namespace {

/// The motion of a point turning with a rotation: a positive angle turns
/// clockwise seen from the axis tip, so a point p moves along
/// (p - origin) x axis (about +z, (100, 0, 0) moves toward -y).
Vec3 arcMotion(const Rotation& r, const Vec3& p) {
  return (p - r.origin).cross(r.axis) * (r.angle < 0 ? Real(-1) : Real(1));
}

/// The cosine of a contact normal with a motion (0 for no motion).
Real cosineWithMotion(const Vec3& normal, const Vec3& motion) {
  const Real len = motion.length();
  return len > 0 ? normal.dot(motion) / len : 0;
}

/// A few trace-model kinds of about the size of a player's or a crate's.
std::vector<TraceModel> traceModels() {
  return {*TraceModel::box({{-16, -16, 0}, {16, 16, 40}}),
          *TraceModel::cylinder({{-12, -12, -20}, {12, 12, 20}}, 8),
          *TraceModel::cone({{-10, -10, -14}, {10, 10, 14}}, 6),
          *TraceModel::octahedron({{-10, -10, -10}, {10, 10, 10}}),
          *TraceModel::dodecahedron({{-9, -9, -9}, {9, 9, 9}}),
          *TraceModel::bone(40, 12)};
}

/// A small room of boxes and a few tilted convex pieces (so that edges meet
/// at all angles): floor, a block, a ramp-like wedge, a tilted slab and a
/// pyramid.
CollisionModel handMadeModel() {
  const Vec3 wedge[6] = {{40, -60, 0}, {120, -60, 0}, {40, -60, 50}, {40, 20, 0}, {120, 20, 0}, {40, 20, 50}};
  const Vec3 slab[8] = {{-120, 40, 10}, {-40, 60, 30}, {-120, 120, 20}, {-40, 140, 40},
                        {-120, 40, 22}, {-40, 60, 42}, {-120, 120, 32}, {-40, 140, 52}};
  const Vec3 pyramid[5] = {{60, 60, 0}, {140, 60, 0}, {60, 140, 0}, {140, 140, 0}, {100, 100, 70}};
  return ModelMaker()
      .addBox({{-160, -160, -16}, {160, 160, 0}})
      .addBox({{-100, -100, 0}, {-20, -20, 60}})
      .addConvex(*TraceModel::convexHull(wedge))
      .addConvex(*TraceModel::convexHull(slab))
      .addConvex(*TraceModel::convexHull(pyramid))
      .build();
}

/// Counts of the contacts a property test checked, by start (free / in
/// solid) and contact type, and the ones that broke the property.
struct NormalTally {
  std::array<std::array<int, 4>, 2> checked{};  // [startSolid][ContactType]
  int failures = 0;
  std::string firstFailures;

  void add(bool startSolid, ContactType type, Real cosine, const std::string& what) {
    ++checked[startSolid][std::size_t(type)];
    if (cosine <= tol::kRotationContactTangentCosine) return;
    if (++failures <= 5) firstFailures += what + " cosine " + std::to_string(cosine) + "\n";
  }
  int total(bool startSolid) const {
    int n = 0;
    for (int c : checked[startSolid]) n += c;
    return n;
  }
  std::string summary() const {
    char buf[256];
    std::snprintf(buf, sizeof buf,
                  "free starts: %d edge, %d modelvertex, %d trmvertex; starts in solid: %d edge, %d "
                  "modelvertex, %d trmvertex",
                  checked[0][1], checked[0][2], checked[0][3], checked[1][1], checked[1][2], checked[1][3]);
    return buf;
  }
};

/// A uniformly random point of a box.
Vec3 randomPoint(std::mt19937& rng, const Bounds& b) {
  std::uniform_real_distribution<float> unit(0, 1);
  const Vec3 size = b.max - b.min;
  return b.min + Vec3{unit(rng) * size.x, unit(rng) * size.y, unit(rng) * size.z};
}

Vec3 randomUnit(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(-1, 1);
  for (;;) {
    Vec3 v{unit(rng), unit(rng), unit(rng)};
    if (v.lengthSquared() > 0.01f && v.lengthSquared() <= 1) return v.normalized();
  }
}

/// `count` random rotations of every trace-model kind within `area` (starts
/// free and in solid), every contact's normal against its point's motion.
NormalTally rotationNormals(const CollisionModel& model, const Bounds& area, int count, unsigned seed) {
  const std::vector<TraceModel> trms = traceModels();
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0, 1), angle(-300, 300);
  QueryWork work;
  NormalTally tally;
  for (int n = 0; n < count; ++n) {
    RotationQuery q;
    q.trm = &trms[std::size_t(n) % trms.size()];
    q.trmAxis = Rotation({}, randomUnit(rng), angle(rng)).matrix();
    q.start = randomPoint(rng, area);
    // the axis through the trace model or up to 60 units beside it
    const Vec3 origin = q.start + randomUnit(rng) * (unit(rng) * 60);
    q.rotation = Rotation(origin, randomUnit(rng), angle(rng));
    q.detectStartSolid = true;
    const TraceResult r = rotate(model, q, work);
    if (r.fraction == 1 || r.contact.type == ContactType::None) continue;
    const Vec3 motion = arcMotion(q.rotation, r.contact.point);
    // A contact point on the axis does not move: no direction to oppose.
    if (motion.length() < tol::kRotationAxisEpsilon) continue;
    tally.add(r.startSolid, r.contact.type, cosineWithMotion(r.contact.normal, motion),
              "rotation " + std::to_string(n) + " (" + toString(r.contact.type) +
                  (r.startSolid ? ", start in solid)" : ", free start)") + " fraction " +
                  std::to_string(r.fraction));
  }
  return tally;
}

// The bundled map the properties also run on (synthetic, CC0).
const char* const kBundledMap = "maps/synthetic/box_room.map";

}  // namespace

TEST(RotationNormals, HandComputedEdgeContactOpposesTheMotion) {
  // A block x -100..0, z -100..0 (its edge along y at x = 0, z = 0) and a
  // wedge whose lowest edge runs from (-10, 0, 10) to (10, 0, -10) relative
  // to it, started at (0, 0, 20). Turning by +10 degrees about +x through
  // (0, -300, 20), the wedge's point at x = 0, y = 0 (300 units from the
  // axis) moves along (p - o) x x = (0, 300, 0) x (1, 0, 0) = (0, 0, -300):
  // straight down onto the block's edge, reached when it has come down 20
  // units, at asin(20 / 300) = 3.82 degrees. The contact plane holds the
  // block's edge (along y) and the wedge's edge (along (1, 0, -1)), turned a
  // little about x: normal close to (1, 0, 1) / sqrt 2, up, against the
  // downward motion. Turning the other way (-10 degrees) about the same
  // axis through (0, 300, 20) comes down on the same edge from the other
  // side of the axis: the same normal.
  const CollisionModel block = ModelMaker().addBox({{-100, -100, -100}, {0, 100, 0}}).build();
  const Vec3 wedgePoints[4] = {{-10, 0, 10}, {10, 0, -10}, {-3, -4, 10}, {-3, 4, 10}};
  const TraceModel wedge = *TraceModel::convexHull(wedgePoints);
  QueryWork work;
  for (const Real side : {Real(1), Real(-1)}) {
    RotationQuery q;
    q.trm = &wedge;
    q.start = {0, 0, 20};
    q.rotation = Rotation({0, -300 * side, 20}, {1, 0, 0}, 10 * side);
    const TraceResult r = rotate(block, q, work);
    ASSERT_LT(r.fraction, 1);
    EXPECT_EQ(r.contact.type, ContactType::Edge);
    EXPECT_NEAR(r.fraction * 10, std::asin(20.0 / 300) * 180 / 3.14159265358979, 0.1);
    EXPECT_GT(r.contact.normal.dot(Vec3{1, 0, 1}) / std::sqrt(Real(2)), 0.99f)
        << r.contact.normal.x << " " << r.contact.normal.y << " " << r.contact.normal.z;
    EXPECT_LT(cosineWithMotion(r.contact.normal, arcMotion(q.rotation, r.contact.point)), -0.5f);
  }
}

TEST(RotationNormals, EveryContactOpposesItsPointsMotionOnAHandMadeModel) {
  const CollisionModel model = handMadeModel();
  const Bounds area{{-170, -170, -30}, {170, 170, 90}};
  const NormalTally t = rotationNormals(model, area, 10000, 34);
  EXPECT_EQ(t.failures, 0) << t.firstFailures << t.summary();
  // Both kinds of start, and every contact type, were checked.
  EXPECT_GT(t.total(false), 200) << t.summary();
  EXPECT_GT(t.total(true), 200) << t.summary();
  for (int solid = 0; solid < 2; ++solid)
    for (int type = 1; type < 4; ++type) EXPECT_GT(t.checked[solid][type], 5) << t.summary();
  std::printf("checked %s\n", t.summary().c_str());
}

TEST(RotationNormals, EveryContactOpposesItsPointsMotionOnABundledMap) {
  const std::vector<ModelPtr> models = test::buildMapModels(test::dataFile(kBundledMap));
  ASSERT_FALSE(models.empty());
  const CollisionModel& world = *models[0];
  Bounds area = world.bounds();
  area = area.expanded(-8);
  const NormalTally t = rotationNormals(world, area, 10000, 341);
  EXPECT_EQ(t.failures, 0) << t.firstFailures << t.summary();
  EXPECT_GT(t.total(false), 100) << t.summary();
  EXPECT_GT(t.total(true), 100) << t.summary();
  std::printf("checked %s\n", t.summary().c_str());
}

TEST(TranslationNormals, EveryContactOpposesTheMotion) {
  // Checked the same way as rotations: every translation contact, and every
  // contact of contacts(), faces against the direction of the move.
  const CollisionModel model = handMadeModel();
  const std::vector<TraceModel> trms = traceModels();
  const Bounds area{{-170, -170, -30}, {170, 170, 90}};
  std::mt19937 rng(3434);
  std::uniform_real_distribution<float> length(0, 200), angle(-180, 180);
  QueryWork work;
  NormalTally traces, touches;
  for (int n = 0; n < 3000; ++n) {
    const TraceModel& trm = trms[std::size_t(n) % trms.size()];
    const Mat3 trmAxis = Rotation({}, randomUnit(rng), angle(rng)).matrix();
    const Vec3 start = randomPoint(rng, area);
    const Vec3 dir = randomUnit(rng);
    const Real depth = length(rng);
    TranslationQuery q;
    q.trm = &trm;
    q.trmAxis = trmAxis;
    q.start = start;
    q.end = start + dir * depth;
    q.detectStartSolid = true;
    const TraceResult r = translate(model, q, work);
    const std::string what = "translation " + std::to_string(n);
    if (r.fraction < 1 && r.contact.type != ContactType::None)
      traces.add(r.startSolid, r.contact.type, cosineWithMotion(r.contact.normal, dir), what);
    ContactsQuery c;
    c.trm = &trm;
    c.trmAxis = trmAxis;
    c.start = start;
    c.dir = dir;
    c.depth = depth;
    for (const ContactInfo& info : contacts(model, c, work).contacts)
      touches.add(r.startSolid, info.type, cosineWithMotion(info.normal, dir),
                  "contacts " + std::to_string(n));
  }
  EXPECT_EQ(traces.failures, 0) << traces.firstFailures << traces.summary();
  EXPECT_EQ(touches.failures, 0) << touches.firstFailures << touches.summary();
  EXPECT_GT(traces.total(false), 200) << traces.summary();
  EXPECT_GT(traces.total(true), 200) << traces.summary();
  EXPECT_GT(touches.total(false) + touches.total(true), 200) << touches.summary();
  std::printf("translations: %s\ncontacts: %s\n", traces.summary().c_str(), touches.summary().c_str());
}

namespace {

/// A rotation line of the shared reference files (spec/query-format.md) and
/// what cmkit answers now: the original's fraction and the normal that
/// opposes the contact point's motion.
struct ReferenceRotation {
  const char* where;  ///< reference file and result line
  const char* query;
  double fraction;
  Vec3 normal;
};

/// Answers `r.query` on `models` and checks the fraction, the normal and
/// that the normal opposes the contact point's motion.
void expectReferenceRotation(std::span<const ModelPtr> models, const ReferenceRotation& r, QueryWork& work) {
  SCOPED_TRACE(r.where);
  const std::string answer = answerQueryLine(models, r.query, work);
  const detail::Fields got(answer);
  ASSERT_TRUE(got.has("fraction") && got.has("normal") && got.has("point")) << answer;
  // The original's fraction (float); the double build rounds otherwise and
  // lands up to a few 1e-4 away on these lines.
  constexpr double kFractionTolerance = std::is_same_v<Real, float> ? 1e-4 : 1e-3;
  EXPECT_NEAR(test::numbers(got.value("fraction")).at(0), r.fraction, kFractionTolerance) << answer;
  const auto n = test::numbers(got.value("normal")), p = test::numbers(got.value("point"));
  ASSERT_EQ(n.size(), 3u);
  ASSERT_EQ(p.size(), 3u);
  const Vec3 normal{n[0], n[1], n[2]};
  EXPECT_LT((normal - r.normal).length(), 1e-3f) << answer;
  const detail::Fields q(r.query);
  const auto o = test::numbers(q.value("rotorigin")), a = test::numbers(q.value("rotaxis"));
  const Rotation rotation({o[0], o[1], o[2]}, {a[0], a[1], a[2]}, test::numbers(q.value("angle")).at(0));
  EXPECT_LT(cosineWithMotion(normal, arcMotion(rotation, {p[0], p[1], p[2]})), 0) << answer;
}

}  // namespace

TEST(RotationNormals, ReferenceEdgeContactsWhoseNormalWasFlipped) {
  // Lines of reference/box_room where the original's edge-contact normal
  // opposes the motion and cmkit's once followed it (agree.py: "normal
  // flipped"), and line 1353, where the original's follows the motion
  // (cosine 0.32) and cmkit's is the opposite. Same fraction as the
  // original on every line.
  const std::vector<ModelPtr> models = test::buildMapModels(test::dataFile(kBundledMap));
  ASSERT_FALSE(models.empty());
  const ReferenceRotation lines[] = {
      {"box_room 85",
       "rotation trm=box:-23,-25.5,0,23,25.5,32 start=270.424591,273.824249,23.0348358 "
       "rotorigin=312.821564,320.190765,71.2643585 rotaxis=0,0,-1 angle=167.705078 mask=solid,opaque",
       0.0785015151,
       {-0.227757692f, 0.973717809f, 0}},
      {"box_room 963",
       "rotation trm=polygon:19.5,0,0;13.75,13.75,0;-0.0625,19.5,0;-13.8125,13.75,0;-19.5,-0.0625,0;"
       "-13.8125,-13.8125,0;0,-19.5,0;13.75,-13.8125,0 start=264.393433,243.096405,67.0977783 "
       "rotorigin=229.263367,238.617081,116.529724 rotaxis=1,0,0 angle=238.777771",
       0.0964241847,
       {0.357770324f, 0.933809519f, 0}},
      {"box_room 1403",
       "rotation trm=cylinder:3:-24.5,-24.5,0,24.5,24.5,40 start=399.717163,-198.56012,95.3643036 "
       "rotorigin=410.881744,-153.693207,132.60318 rotaxis=0,0,-1 angle=-242.430359",
       0.0436541922,
       {1, 0, 0}},
      {"box_room 1621",
       "rotation trm=octahedron:-29,-29,0,29,29,51 start=-256.680817,-386.455078,86.8413239 "
       "rotorigin=-297,-328,24 "
       "rotaxis=1,0,0 angle=-191.210175 "
       "trmaxis=-0.57091713,-0.730513871,-0.374704003,-0.662120044,0.679532766,"
       "-0.315962583,0.485438704,0.0677105784,-0.871644735",
       0.00139905605,
       {0.558621466f, 0.497653693f, 0.663538158f}},
      {"box_room 1919",
       "rotation trm=box:-21.5,-21.5,0,21.5,21.5,12 start=398,-227,82 rotorigin=388,-247,57 rotaxis=0,0,-1 "
       "angle=216.953003 trmaxis=-0.813764691,-0.398616582,-0.422956377,-0.277602464,-0.372772336,0.88542521,"
       "-0.510611534,0.837941408,0.192691803",
       0.160292342,
       {0.999848723f, 0, 0.017392572f}},
      {"box_room 1353 (the original's normal, (-0.999, 0.035, 0), follows the motion)",
       "rotation trm=box:-26.5,-26.5,-6.5,26.5,26.5,6.5 start=301.978119,285.028381,222.096069 "
       "rotorigin=360.429535,299.391663,178.865112 rotaxis=0,0,1 angle=18.0380859",
       0.111040406,
       {0.999388993f, -0.0349512808f, 0}},
  };
  QueryWork work;
  for (const ReferenceRotation& r : lines) expectReferenceRotation(models, r, work);
}

TEST(RotationNormals, ReferenceModelVertexContactFacesTheTurnedPolygon) {
  // reference-proc/box_room_proc line 1466: a box turns 123 degrees (0.734
  // of -167.6 about -z) until a floor vertex (448, -128, 0) meets its face
  // whose normal is -x at the start. The original reports that start
  // normal's opposite, (1, 0, 0), which follows the vertex's motion
  // (cosine 0.999: the face has turned far past it); cmkit reports the face
  // where it meets the vertex: its normal at the end is -endAxis[0], so the
  // contact normal is endAxis[0] = (-0.544, -0.839, 0).
  const std::vector<ModelPtr> models =
      test::buildMapModels(test::dataFile("maps/synthetic-proc/box_room_proc.map"));
  ASSERT_FALSE(models.empty());
  QueryWork work;
  expectReferenceRotation(
      models,
      {"box_room_proc 1466",
       "rotation trm=box:-20.75,-20.75,-24,20.75,20.75,24 start=404.473816,-217.815323,16.75 "
       "rotorigin=445.111847,-199.588928,-39.6263275 rotaxis=0,0,-1 angle=-167.606232",
       0.733624339,
       {-0.544053555f, -0.839050412f, 0}},
      work);
}
