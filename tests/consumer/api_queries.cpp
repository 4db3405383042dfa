// Uses the installed cmkit package the way the public query API is meant to
// be used (issue "API II"): a model sealed by CollisionModel::create, and
// every query kind taking its XxxQuery and returning its XxxResult with a
// top-level status. The static_asserts pin the signatures; the run checks
// answers computed by hand on a 32-unit solid cube.
#include <cmkit/contents.h>
#include <cmkit/model.h>
#include <cmkit/query.h>
#include <cmkit/trace_model.h>

#include <cmath>
#include <cstdio>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using cmkit::CollisionModel;
using cmkit::QueryWork;

// ---- the signatures -------------------------------------------------------

// Declared only: named in unevaluated operands.
const CollisionModel& aModel();
QueryWork& aWork();

static_assert(std::is_same_v<decltype(cmkit::translate(aModel(), cmkit::TranslationQuery{}, aWork())),
                             cmkit::TraceResult>);
static_assert(
    std::is_same_v<decltype(cmkit::rotate(aModel(), cmkit::RotationQuery{}, aWork())), cmkit::TraceResult>);
static_assert(std::is_same_v<decltype(cmkit::contentsTest(aModel(), cmkit::ContentsQuery{}, aWork())),
                             cmkit::ContentsResult>);
static_assert(std::is_same_v<decltype(cmkit::pointContents(aModel(), cmkit::PointContentsQuery{}, aWork())),
                             cmkit::PointContentsResult>);
static_assert(std::is_same_v<decltype(cmkit::contacts(aModel(), cmkit::ContactsQuery{}, aWork())),
                             cmkit::ContactsResult>);
static_assert(std::is_same_v<decltype(cmkit::contacts(aModel(), cmkit::ContactsQuery{}, aWork(),
                                                      std::declval<std::vector<cmkit::ContactInfo>&>())),
                             cmkit::QueryStatus>);
static_assert(std::is_same_v<decltype(cmkit::penetration(aModel(), cmkit::PenetrationQuery{}, aWork())),
                             cmkit::PenetrationResult>);
// The results' fields the issue names, with their types.
static_assert(std::is_same_v<decltype(cmkit::TraceResult::status), cmkit::QueryStatus>);
static_assert(std::is_same_v<decltype(cmkit::ContentsResult::status), cmkit::QueryStatus>);
static_assert(std::is_same_v<decltype(cmkit::ContentsResult::contents), std::uint32_t>);
static_assert(std::is_same_v<decltype(cmkit::ContentsResult::trace), cmkit::TraceResult>);
static_assert(std::is_same_v<decltype(cmkit::PointContentsQuery::point), cmkit::Vec3>);
static_assert(std::is_same_v<decltype(cmkit::PointContentsQuery::placement), cmkit::Placement>);
static_assert(std::is_same_v<decltype(cmkit::PointContentsResult::status), cmkit::QueryStatus>);
static_assert(std::is_same_v<decltype(cmkit::PointContentsResult::contents), std::uint32_t>);
static_assert(std::is_same_v<decltype(cmkit::ContactsResult::status), cmkit::QueryStatus>);
static_assert(std::is_same_v<decltype(cmkit::ContactsResult::contacts), std::vector<cmkit::ContactInfo>>);
static_assert(std::is_same_v<decltype(cmkit::PenetrationResult::status), cmkit::QueryStatus>);
// The model is sealed: no default construction, no construction from arrays
// but through create() (tests/sealed_model checks that edits do not compile).
static_assert(!std::is_default_constructible_v<CollisionModel>);
static_assert(!std::is_constructible_v<CollisionModel, cmkit::ModelArrays>);
static_assert(std::is_same_v<decltype(CollisionModel::create(cmkit::ModelArrays{})),
                             cmkit::Result<std::shared_ptr<const CollisionModel>>>);

// ---- the checks -----------------------------------------------------------

int failures = 0;

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "FAILED: %s\n", what);
    ++failures;
  }
}

bool near(cmkit::Real a, double b, double tolerance) { return std::fabs(double(a) - b) <= tolerance; }

// The solid cube [-16, 16]^3: the trace-model conversion's polygons, and one
// brush from their planes added to a copy of its arrays (the leaf root lists
// it), sealed again by create().
cmkit::ModelPtr makeCube() {
  const auto box = cmkit::TraceModel::box({{-16, -16, -16}, {16, 16, 16}});
  if (!box.ok()) return nullptr;
  const cmkit::ModelPtr polygons = cmkit::collisionModelFromTraceModel(*box);
  cmkit::ModelArrays arrays = polygons->arrays();
  cmkit::CmBrush brush;
  brush.bounds = arrays.bounds;
  brush.contents = cmkit::contents::kSolid;
  brush.firstPlane = 0;
  for (const cmkit::CmPolygon& p : arrays.polygons) arrays.brushPlanes.push_back(p.plane);
  brush.numPlanes = std::uint32_t(arrays.brushPlanes.size());
  arrays.brushes.push_back(brush);
  arrays.brushRefs.push_back(0);
  arrays.nodes[0].firstBrushRef = 0;
  arrays.nodes[0].numBrushRefs = 1;
  arrays.name = "cube";
  auto made = CollisionModel::create(std::move(arrays));
  if (!made.ok()) {
    std::fprintf(stderr, "create failed: %s\n", made.error().toString().c_str());
    return nullptr;
  }
  return *made;
}

}  // namespace

int main() {
  const cmkit::ModelPtr cube = makeCube();
  if (!cube) return 1;
  const CollisionModel& model = *cube;
  check(model.name() == "cube" && model.brushes().size() == 1 && model.polygons().size() == 6,
        "create(): one brush, six polygons");
  const auto small = cmkit::TraceModel::box({{-8, -8, -8}, {8, 8, 8}});
  if (!small.ok()) return 1;
  QueryWork work;
  constexpr auto kOk = cmkit::QueryStatus::Ok;

  // translate: the 16-unit box from x = -100 towards the origin touches the
  // face x = -16 at x = -24 and stops 0.25 units before: fraction 0.7575.
  cmkit::TranslationQuery move;
  move.trm = &*small;
  move.start = {-100, 0, 0};
  move.end = {0, 0, 0};
  const cmkit::TraceResult moved = cmkit::translate(model, move, work);
  check(moved.status == kOk, "translate: status ok");
  check(near(moved.fraction, 0.7575, 1e-3) && near(moved.endPos.x, -24.25, 1e-2),
        "translate: fraction, endPos");
  check(near(moved.contact.normal.x, -1, 1e-4), "translate: contact normal -x");
  move.start.x = std::nan("");
  check(cmkit::translate(model, move, work).status == cmkit::QueryStatus::NonFinite,
        "translate: a NaN start is refused");

  // rotate: a point at (0, 20, 0) turned +90 degrees about +x (clockwise
  // seen from +x: towards -z) meets the face y = 16 where cos = 0.8 (36.87
  // degrees), stopping 0.25 units before (y = 16.25: 35.66 degrees).
  cmkit::RotationQuery turn;
  turn.start = {0, 20, 0};
  turn.rotation = cmkit::Rotation({0, 0, 0}, {1, 0, 0}, 90);
  const cmkit::TraceResult turned = cmkit::rotate(model, turn, work);
  check(turned.status == kOk, "rotate: status ok");
  check(turned.fraction > cmkit::Real(35.0 / 90) && turned.fraction < cmkit::Real(36.87 / 90),
        "rotate: fraction");
  check(near(turned.contact.normal.y, 1, 1e-3) && turned.endPos.z < 0,
        "rotate: contact on y = 16, below z = 0");

  // contentsTest: the box at x = 20 reaches x = 12 (inside); at x = 30 it is free.
  cmkit::ContentsQuery at;
  at.trm = &*small;
  at.position = {20, 0, 0};
  const cmkit::ContentsResult inside = cmkit::contentsTest(model, at, work);
  check(inside.status == kOk && inside.contents == cmkit::contents::kSolid && inside.trace.fraction == 0,
        "contentsTest: overlapping");
  at.position = {30, 0, 0};
  const cmkit::ContentsResult free = cmkit::contentsTest(model, at, work);
  check(free.status == kOk && free.contents == 0 && free.trace.fraction == 1, "contentsTest: free");

  // pointContents: the origin is solid; so is (100, 0, 0) with the cube placed there.
  cmkit::PointContentsQuery point;
  point.point = {0, 0, 0};
  const cmkit::PointContentsResult solid = cmkit::pointContents(model, point, work);
  check(solid.status == kOk && solid.contents == cmkit::contents::kSolid, "pointContents: origin solid");
  point.point = {0, 0, 50};
  check(cmkit::pointContents(model, point, work).contents == 0, "pointContents: (0, 0, 50) empty");
  point.point = {100, 0, 0};
  point.placement.origin = {100, 0, 0};
  check(cmkit::pointContents(model, point, work).contents == cmkit::contents::kSolid,
        "pointContents: placed cube");

  // contacts: a point 4 units in front of the face x = -16 moved 10 units at it.
  cmkit::ContactsQuery touch;
  touch.start = {-20, 0, 0};
  touch.dir = {1, 0, 0};
  touch.depth = 10;
  const cmkit::ContactsResult touched = cmkit::contacts(model, touch, work);
  check(touched.status == kOk && !touched.contacts.empty(), "contacts: found");
  for (const cmkit::ContactInfo& c : touched.contacts)
    check(near(c.normal.x, -1, 1e-4) && near(c.dist, 16, 1e-3), "contacts: on the face x = -16");
  std::vector<cmkit::ContactInfo> mine(3);
  check(cmkit::contacts(model, touch, work, mine) == kOk && mine.size() == touched.contacts.size(),
        "contacts: the caller's vector holds the same");

  // penetration: the box at x = 20 is 4 units deep through the face x = 16.
  cmkit::PenetrationQuery stuck;
  stuck.trm = &*small;
  stuck.position = {20, 0, 0};
  const cmkit::PenetrationResult out = cmkit::penetration(model, stuck, work);
  check(out.status == kOk && out.stuck && near(out.depth, 4, 1e-3) && near(out.direction.x, 1, 1e-4) &&
            out.contents == cmkit::contents::kSolid,
        "penetration: 4 units along +x");

  if (failures) return 1;
  std::printf("consumer api ok: translate, rotate, contentsTest, pointContents, contacts, penetration\n");
  return 0;
}
