// The input guards of every public query (QueryStatus, docs/reliability.md):
// refused input gets a status and a defined result, never garbage; a
// slightly drifted axis is re-orthonormalised, one within the drift epsilon
// passed on unchanged.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/tolerances.h"
#include "guard_values.h"
#include "query/query_guards.h"
#include "test_support.h"

using namespace cmkit;

namespace {

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();
constexpr Real kInf = std::numeric_limits<Real>::infinity();

TraceModel trm(const char* spec) { return TraceModel::parse(spec).value(); }

}  // namespace

class QueryGuards : public ::testing::Test {
 protected:
  void SetUp() override {
    models_ = test::buildModelsFromText(
        "Version 2\n{\n\"classname\" \"worldspawn\"\n" +
        test::axialBrush({{-256, -256, -16}, {256, 256, 0}}, "textures/base_wall/lfwall27d") + "}\n");
    ASSERT_EQ(models_.size(), 1u);
  }
  const CollisionModel& floor() const { return *models_[0]; }
  TraceResult drop(const Mat3& trmAxis, const Vec3& start, const Vec3& end, const Placement& placement = {}) {
    return translate(floor(), {&box_, trmAxis, start, end, contents::kMaskSolid, placement, false}, work_);
  }
  std::vector<ModelPtr> models_;
  TraceModel box_ = trm("box:-16,-16,0,16,16,72");
  QueryWork work_;
};

void expectRefused(const TraceResult& r, QueryStatus status, const Vec3& start) {
  EXPECT_EQ(r.status, status) << toString(r.status);
  EXPECT_EQ(r.fraction, 0);
  if (start.isFinite()) {
    EXPECT_EQ(r.endPos, start);
  }
  EXPECT_EQ(r.contact.type, ContactType::None);
  EXPECT_EQ(r.contact.contents, 0u);
}

TEST_F(QueryGuards, ValidInputRunsWithStatusOk) {
  const TraceResult r = drop(Mat3::identity(), {0, 0, 64}, {0, 0, -64});
  EXPECT_EQ(r.status, QueryStatus::Ok);
  EXPECT_FLOAT_EQ(r.endPos.z, 0.25f);  // the clip epsilon above the floor
  EXPECT_STREQ(toString(QueryStatus::Ok), "ok");
}

TEST_F(QueryGuards, TraceModelAxisMustBeARotation) {
  const Vec3 start{0, 0, 64}, end{0, 0, -64};
  const Mat3 mirrored{{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
  expectRefused(drop(mirrored, start, end), QueryStatus::BadTrmAxis, start);
  const Mat3 scaled{{2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  expectRefused(drop(scaled, start, end), QueryStatus::BadTrmAxis, start);
  const Mat3 sheared{{1, 0.3f, 0}, {0, 1, 0}, {0, 0, 1}};
  expectRefused(drop(sheared, start, end), QueryStatus::BadTrmAxis, start);
  const Mat3 nan{{kNaN, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  expectRefused(drop(nan, start, end), QueryStatus::BadTrmAxis, start);
  // A point ignores its axis.
  const TraceResult point =
      translate(floor(), {nullptr, scaled, start, end, contents::kMaskSolid, {}, false}, work_);
  EXPECT_EQ(point.status, QueryStatus::Ok);
}

// Found by fuzz_query: a box 1.3e22 units long made the rotation's walk
// divide inf by inf and convert the NaN to an int (UBSan). Trace models
// beyond 1e9 units are refused by every query, like positions that far.
TEST_F(QueryGuards, HugeTraceModelsAreRefused) {
  const TraceModel huge = trm("box:-51,-12888888888888888888888,-25,28,282,5");
  const Vec3 start{0, 0, 64};
  expectRefused(
      translate(floor(), {&huge, Mat3::identity(), start, {0, 0, -64}, contents::kMaskSolid, {}, false},
                work_),
      QueryStatus::OutOfRange, start);
  RotationQuery r;
  r.trm = &huge;
  r.start = start;
  r.rotation = Rotation({243, 0, 64}, {0, 0, -1}, 60.0334473f);
  r.contentMask = contents::kMaskSolid;
  expectRefused(rotate(floor(), r, work_), QueryStatus::OutOfRange, start);
  EXPECT_EQ(contentsTest(floor(), {&huge, Mat3::identity(), start, contents::kMaskSolid, {}}, work_).status,
            QueryStatus::OutOfRange);
  ContactsQuery c;
  c.trm = &huge;
  c.start = start;
  c.dir = {0, 0, -1};
  c.depth = 128;
  c.contentMask = contents::kMaskSolid;
  EXPECT_EQ(contacts(floor(), c, work_).status, QueryStatus::OutOfRange);
  // 1e8 units is within range: the query runs.
  const TraceModel large = trm("box:-100000000,-16,0,16,16,72");
  EXPECT_EQ(drop(Mat3::identity(), {0, 0, 64}, {0, 0, -64}).status, QueryStatus::Ok);
  EXPECT_EQ(translate(floor(),
                      {&large, Mat3::identity(), start, {0, 0, -64}, contents::kMaskSolid, {}, false}, work_)
                .status,
            QueryStatus::Ok);
}

TEST_F(QueryGuards, SlightlyDriftedAxisIsReorthonormalised) {
  // 45 degrees about z, rows scaled by 1.001: accepted (drift 2e-3 is below
  // tol::kAxisRejectTolerance) and used as the orthonormalised rotation.
  const Real c = std::sqrt(Real(0.5));
  const Mat3 exact{{c, c, 0}, {-c, c, 0}, {0, 0, 1}};
  const Mat3 drifted{exact.rows[0] * 1.001f, exact.rows[1] * 1.001f, exact.rows[2]};
  const TraceResult a = drop(exact, {0, 0, 64}, {0, 0, -64});
  const TraceResult b = drop(drifted, {0, 0, 64}, {0, 0, -64});
  EXPECT_EQ(b.status, QueryStatus::Ok);
  EXPECT_NEAR(b.fraction, a.fraction, 1e-6f);
  EXPECT_NEAR(b.contact.normal.length(), 1, 1e-6f);
}

// The guard passes a turned axis on unchanged when it is orthonormal within
// tol::kAxisDriftEpsilon and right-handed (a quick check in float lanes),
// else re-orthonormalised by validateAxis: the quick check decides as
// Mat3::orthonormalityError does. Rotations drifted by scaling a row or
// shearing it toward the next, from a fifth of the epsilon to three times
// it, end with the axis as given exactly when their error is within the
// epsilon, else as validateAxis makes it.
TEST_F(QueryGuards, AnAxisPassesUnchangedExactlyWhenItsDriftIsWithinTheEpsilon) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1, 1), angle(-3.1f, 3.1f), drift(0.2f, 3.0f);
  int unchanged = 0, normalised = 0;
  for (int i = 0; i < 2000; ++i) {
    Vec3 dir{unit(rng), unit(rng), unit(rng)};
    const Real length = std::sqrt(dir.lengthSquared());
    if (length < Real(0.1)) continue;
    Mat3 m = Mat3::fromAxisAngle(dir * (1 / length), angle(rng));
    const Real e = tol::kAxisDriftEpsilon * drift(rng);
    const std::size_t r = std::size_t(i % 3);
    if (i % 2)
      m.rows[r] = m.rows[r] * (1 + e / 2);  // length squared off by about e
    else
      m.rows[r] = m.rows[r] + m.rows[(r + 1) % 3] * e;  // a dot product off by about e
    const TraceResult got = drop(m, {0, 0, 64}, {0, 0, -64});
    ASSERT_EQ(got.status, QueryStatus::Ok) << i;
    const bool within = m.orthonormalityError() <= tol::kAxisDriftEpsilon && m.determinant() > 0;
    Mat3 expected = m;
    if (!within) {
      const Result<Mat3> fixed = validateAxis(m);
      ASSERT_TRUE(fixed) << i;
      expected = *fixed;
    }
    EXPECT_EQ(std::memcmp(&got.endAxis, &expected, sizeof(Mat3)), 0)
        << i
        << (within ? ": within the epsilon, not passed unchanged" : ": beyond it, not re-orthonormalised");
    ++(within ? unchanged : normalised);
  }
  EXPECT_GT(unchanged, 300);
  EXPECT_GT(normalised, 300);
  // An infinite element, or one whose square overflows, is refused.
  const Vec3 start{0, 0, 64}, end{0, 0, -64};
  const Real inf = std::numeric_limits<Real>::infinity();
  expectRefused(drop(Mat3{{inf, 0, 0}, {0, 1, 0}, {0, 0, 1}}, start, end), QueryStatus::BadTrmAxis, start);
  expectRefused(drop(Mat3{{0, 1, 0}, {Real(1e30), 0, 0}, {0, 0, 1}}, start, end), QueryStatus::BadTrmAxis,
                start);
}

TEST_F(QueryGuards, ModelAxisMustBeARotation) {
  const Vec3 start{0, 0, 64}, end{0, 0, -64};
  Placement scaled;
  scaled.axis = Mat3{{2, 0, 0}, {0, 2, 0}, {0, 0, 2}};
  expectRefused(drop(Mat3::identity(), start, end, scaled), QueryStatus::BadModelAxis, start);
  Placement nan;
  nan.axis = Mat3{{1, 0, 0}, {0, kNaN, 0}, {0, 0, 1}};
  expectRefused(drop(Mat3::identity(), start, end, nan), QueryStatus::BadModelAxis, start);
  Placement nanOrigin;
  nanOrigin.origin = {kNaN, 0, 0};
  expectRefused(drop(Mat3::identity(), start, end, nanOrigin), QueryStatus::NonFinite, start);
  const PointContentsResult badAxis = pointContents(floor(), {{0, 0, -8}, nan}, work_);
  EXPECT_EQ(badAxis.status, QueryStatus::BadModelAxis);
  EXPECT_EQ(badAxis.contents, 0u);
  const PointContentsResult scaledAxis = pointContents(floor(), {{0, 0, -8}, scaled}, work_);
  EXPECT_EQ(scaledAxis.status, QueryStatus::BadModelAxis);
  EXPECT_EQ(scaledAxis.contents, 0u);
  const PointContentsResult badOrigin = pointContents(floor(), {{0, 0, -8}, nanOrigin}, work_);
  EXPECT_EQ(badOrigin.status, QueryStatus::NonFinite);
  EXPECT_EQ(badOrigin.contents, 0u);
  const PointContentsResult inside = pointContents(floor(), {{0, 0, -8}, {}}, work_);
  EXPECT_EQ(inside.status, QueryStatus::Ok);
  EXPECT_EQ(inside.contents, contents::kSolid | contents::kOpaque);
}

TEST_F(QueryGuards, PositionsMustBeFiniteAndInRange) {
  expectRefused(drop(Mat3::identity(), {kNaN, 0, 64}, {0, 0, -64}), QueryStatus::NonFinite, {kNaN, 0, 64});
  expectRefused(drop(Mat3::identity(), {0, 0, 64}, {0, kInf, -64}), QueryStatus::NonFinite, {0, 0, 64});
  // A move of 3e38 used to end at infinity.
  expectRefused(drop(Mat3::identity(), {0, 0, 64}, {3e38f, 0, 64}), QueryStatus::OutOfRange, {0, 0, 64});
  const TraceResult far = drop(Mat3::identity(), {0, 0, 64}, {1e9f, 0, 64});  // the limit itself runs
  EXPECT_EQ(far.status, QueryStatus::Ok);
  EXPECT_EQ(far.fraction, 1);
  // Position tests and point contents at NaN are not "inside".
  // The status of a contents test is on the result (and on its trace).
  const ContentsResult c = contentsTest(floor(), {&box_, Mat3::identity(), {kNaN, 0, 0}, 1, {}}, work_);
  EXPECT_EQ(c.status, QueryStatus::NonFinite);
  EXPECT_EQ(c.trace.status, QueryStatus::NonFinite);
  EXPECT_EQ(c.contents, 0u);
  const ContentsResult p = contentsTest(floor(), {nullptr, Mat3::identity(), {kNaN, 0, -8}, 1, {}}, work_);
  EXPECT_EQ(p.status, QueryStatus::NonFinite);
  EXPECT_EQ(p.contents, 0u);
  const ContentsResult ok = contentsTest(floor(), {&box_, Mat3::identity(), {0, 0, -8}, 1, {}}, work_);
  EXPECT_EQ(ok.status, QueryStatus::Ok);
  EXPECT_EQ(ok.trace.status, QueryStatus::Ok);
  EXPECT_NE(ok.contents, 0u);
  // pointContents refuses a NaN or far point with its status (contents 0,
  // as before it had a status).
  const PointContentsResult nanPoint = pointContents(floor(), {{kNaN, kNaN, kNaN}, {}}, work_);
  EXPECT_EQ(nanPoint.status, QueryStatus::NonFinite);
  EXPECT_EQ(nanPoint.contents, 0u);
  const PointContentsResult farPoint = pointContents(floor(), {{0, 0, -2e9f}, {}}, work_);
  EXPECT_EQ(farPoint.status, QueryStatus::OutOfRange);
  EXPECT_EQ(farPoint.contents, 0u);
  EXPECT_EQ(pointContents(floor(), {{0, 0, -8}, {}}, work_).contents, contents::kSolid | contents::kOpaque);
  // penetration refuses likewise: not stuck.
  const PenetrationResult pen = penetration(floor(), {&box_, Mat3::identity(), {0, kNaN, -8}, 1, {}}, work_);
  EXPECT_EQ(pen.status, QueryStatus::NonFinite);
  EXPECT_FALSE(pen.stuck);
  const PenetrationResult farPen =
      penetration(floor(), {&box_, Mat3::identity(), {0, 0, -8}, 1, {{3e9f, 0, 0}, {}}}, work_);
  EXPECT_EQ(farPen.status, QueryStatus::OutOfRange);
  EXPECT_FALSE(farPen.stuck);
  EXPECT_EQ(penetration(floor(), {&box_, Mat3::identity(), {0, 0, -8}, 1, {}}, work_).status,
            QueryStatus::Ok);
}

TEST_F(QueryGuards, ContactsNeedAFiniteMove) {
  ContactsQuery q{&box_, Mat3::identity(), {0, 0, 8}, {0, 0, -1}, 16, 1, {}, 8, {}};
  const ContactsResult ok = contacts(floor(), q, work_);
  EXPECT_EQ(ok.status, QueryStatus::Ok);
  EXPECT_FALSE(ok.contacts.empty());
  q.depth = kNaN;
  const ContactsResult nan = contacts(floor(), q, work_);
  EXPECT_EQ(nan.status, QueryStatus::NonFinite);
  EXPECT_TRUE(nan.contacts.empty());
  q.depth = 3e38f;
  q.dir = {0, 0, -10};
  EXPECT_EQ(contacts(floor(), q, work_).status, QueryStatus::OutOfRange);
}

TEST_F(QueryGuards, RotationAxisMustBeUnitAndAngleFinite) {
  auto turn = [&](const Vec3& axis, Real angle) {
    return rotate(floor(),
                  {&box_, Mat3::identity(), {0, 0, 64}, Rotation({0, 0, 64}, axis, angle), 1, {}, false},
                  work_);
  };
  EXPECT_EQ(turn({0, 0, 1}, 90).status, QueryStatus::Ok);
  expectRefused(turn({0, 0, 10}, 90), QueryStatus::BadRotationAxis, {0, 0, 64});
  expectRefused(turn({0, 0, 0}, 90), QueryStatus::BadRotationAxis, {0, 0, 64});
  expectRefused(turn({0, kNaN, 1}, 90), QueryStatus::NonFinite, {0, 0, 64});
  expectRefused(turn({0, 0, 1}, kNaN), QueryStatus::NonFinite, {0, 0, 64});
  expectRefused(turn({0, 0, 1}, kInf), QueryStatus::NonFinite, {0, 0, 64});
  // Nearly unit (1.002): normalised, the same turn as the unit axis.
  const TraceResult near = turn({0, 0, 1.002f}, 90);
  const TraceResult unit = turn({0, 0, 1}, 90);
  EXPECT_EQ(near.status, QueryStatus::Ok);
  EXPECT_EQ(near.endAxis, unit.endAxis);
  EXPECT_EQ(near.fraction, unit.fraction);
}

TEST(QueryGuardsCli, QueryShowsTheRefusal) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the CLI is not built";
  const test::ScratchDir scratch("guards_cli");
  const std::filesystem::path& dir = scratch.path();
  {
    std::ofstream map(dir / "floor.map");
    map << "Version 2\n{\n\"classname\" \"worldspawn\"\n"
        << test::axialBrush({{-256, -256, -16}, {256, 256, 0}}, "textures/base_wall/lfwall27d") << "}\n";
    std::ofstream q(dir / "q.txt");
    q << "translation trm=box:-16,-16,0,16,16,72 start=0,0,64 end=3e38,0,64\n"
         "translation trm=box:-16,-16,0,16,16,72 start=0,0,64 end=0,0,-64\n";
  }
  int rc = 0;
  const std::string out =
      test::runCapture(std::string(CMKIT_CLI_PATH) + " query " + (dir / "floor.map").string() + " " +
                           (dir / "q.txt").string() + " 2>/dev/null",
                       rc);
  EXPECT_EQ(rc, 3);  // every line written; some are error= (cmkit query --help, exit codes)
  EXPECT_NE(
      out.find(
          "error=refused: a coordinate, the end of the move or the trace model's size is beyond 1e9 units"),
      std::string::npos)
      << out;
  EXPECT_NE(out.find("fraction="), std::string::npos) << out;
}

// translate() and contentsTest() answer the usual query (its guard's
// checks passed with nothing to change) from the caller's query itself,
// without the guard's copy (detail::passesGuardUnchanged). For every
// float of start, end, origin, placement axis and trace-model axis set in
// turn to values at and past the limits: wherever the shortcut is taken,
// the guard accepts that query and leaves it bit for bit as it was; and the
// shortcut is taken for the plain query. A box, and boxes reaching past the
// range above and below (refused by their size alone).
TEST(QueryGuardsShortcut, TheUsualQueryIsOneTheGuardPassesUnchanged) {
  const std::vector<Real> rangeValues = test::rangeEdgeValues(), axisValues = test::axisEdgeValues();
  const TraceModel box = trm("box:-16,-16,0,16,16,72");
  const TraceModel huge = trm("box:-16,-16,0,1e20,16,72"), hugeBelow = trm("box:-16,-1e20,0,16,16,72");
  const auto sameBits = [](const auto& a, const auto& b) { return std::memcmp(&a, &b, sizeof(a)) == 0; };
  int taken = 0, notTaken = 0;
  for (const TraceModel* shape : {&box, &huge, &hugeBelow, static_cast<const TraceModel*>(nullptr)})
    for (int f = 0; f < 27; ++f)
      for (const Real v : f < 9 ? rangeValues : axisValues) {
        TranslationQuery q{shape, Mat3::identity(), {1, 2, 3}, {4, 5, 6}, contents::kMaskSolid, {}, false};
        Real* value = f < 3    ? &q.start[f]
                      : f < 6  ? &q.end[f - 3]
                      : f < 9  ? &q.placement.origin[f - 6]
                      : f < 18 ? &q.placement.axis[(f - 9) / 3][(f - 9) % 3]
                               : &q.trmAxis[(f - 18) / 3][(f - 18) % 3];
        *value = v;
        ContentsQuery c{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
        const bool translationShortcut = detail::passesGuardUnchanged(q);
        const bool shortcut = detail::passesGuardUnchanged(c);
        TranslationQuery t = q;
        const QueryStatus ts = detail::guardTranslation(t);
        const QueryStatus cs = detail::guardContents(c);
        if (translationShortcut) {
          EXPECT_EQ(ts, QueryStatus::Ok) << "float " << f << " = " << v;
          EXPECT_TRUE(sameBits(t.start, q.start) && sameBits(t.end, q.end) &&
                      sameBits(t.trmAxis, q.trmAxis) && sameBits(t.placement, q.placement))
              << "float " << f << " = " << v;
        }
        if (shortcut) {
          EXPECT_EQ(cs, QueryStatus::Ok) << "float " << f << " = " << v;
          EXPECT_TRUE(sameBits(c.position, q.start) && sameBits(c.trmAxis, q.trmAxis) &&
                      sameBits(c.placement, q.placement))
              << "float " << f << " = " << v;
        }
        taken += translationShortcut;
        notTaken += !shortcut;
      }
  EXPECT_GT(taken, 50);  // both ways were met
  EXPECT_GT(notTaken, 50);
  const TranslationQuery plain{&box, Mat3::identity(), {1, 2, 3}, {4, 5, 6}, contents::kMaskSolid, {}, false};
  EXPECT_TRUE(detail::passesCommonChecksUnchanged(plain.start, plain.placement, plain.trm, plain.trmAxis));
  EXPECT_FALSE(detail::passesCommonChecksUnchanged(plain.start, plain.placement, &huge, plain.trmAxis));
  EXPECT_FALSE(detail::passesCommonChecksUnchanged(plain.start, plain.placement, &hugeBelow, plain.trmAxis));
}
