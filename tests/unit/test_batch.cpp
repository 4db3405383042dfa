// Batch queries (cmkit/batch.h): a batch gives, bit for bit, what a loop of
// single queries gives, at any thread count and chunk size; progress and
// cancelling; empty batches; inputs of the wrong length are refused.
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "test_support.h"

using namespace cmkit;

namespace {

// Every field as hexadecimal floats: equal strings are equal bits.
std::string bits(const Vec3& v) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "%a,%a,%a", double(v.x), double(v.y), double(v.z));
  return buf;
}
std::string bits(const ContactInfo& c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, " %a %u %d %d %d %a ", double(c.dist), c.contents, c.material,
                c.modelFeature, c.trmFeature, double(c.angle));
  return std::to_string(int(c.type)) + " " + bits(c.point) + " " + bits(c.normal) + buf;
}
std::string bits(const TraceResult& r) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%a %d %d ", double(r.fraction), int(r.startSolid), int(r.status));
  return buf + bits(r.endPos) + " " + bits(r.endAxis.rows[0]) + bits(r.endAxis.rows[1]) +
         bits(r.endAxis.rows[2]) + " " + bits(r.contact);
}
std::string bits(const ContentsResult& r) {
  return std::to_string(int(r.status)) + " " + std::to_string(r.contents) + " " + bits(r.trace);
}
std::string bits(const ContactsResult& r) {
  std::string s = std::to_string(int(r.status)) + " " + std::to_string(r.contacts.size());
  for (const auto& c : r.contacts) s += "|" + bits(c);
  return s;
}
std::string bits(const RayHit& h) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%a %a %d %u %d ", double(h.fraction), double(h.dist), h.polygon, h.contents,
                h.material);
  return buf + bits(h.point) + " " + bits(h.normal);
}
std::string bits(const PointContentsResult& r) {
  return std::to_string(int(r.status)) + " " + std::to_string(r.contents);
}

template <class T>
std::vector<std::string> allBits(const std::vector<T>& v) {
  std::vector<std::string> s;
  for (const auto& x : v) s.push_back(bits(x));
  return s;
}

const std::vector<ModelPtr>& lt4() {
  static const auto models =
      test::buildMapModels(std::filesystem::path(CMKIT_SOURCE_DIR) / "data/maps/lt4/lt4.map");
  return models;
}

std::vector<Vec3> randomPoints(const Bounds& b, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0, 1);
  std::vector<Vec3> v(n);
  for (auto& p : v)
    p = {b.min.x + u(rng) * (b.max.x - b.min.x), b.min.y + u(rng) * (b.max.y - b.min.y),
         b.min.z + u(rng) * (b.max.z - b.min.z)};
  return v;
}

BatchOptions threadsAndChunk(int threads, std::size_t chunkSize = 0) {
  BatchOptions o;
  o.threads = threads;
  o.chunkSize = chunkSize;
  return o;
}

const TraceModel& playerBox() {
  static const TraceModel box = *TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  return box;
}

// The thread counts and chunk sizes every batch is run with.
const std::vector<BatchOptions>& optionVariants() {
  static const std::vector<BatchOptions> variants = [] {
    // 0: the machine's hardware threads
    return std::vector<BatchOptions>{threadsAndChunk(1), threadsAndChunk(2), threadsAndChunk(4),
                                     threadsAndChunk(3, 7), threadsAndChunk(0)};
  }();
  return variants;
}

constexpr std::size_t kQueries = 3000;

}  // namespace

TEST(Batch, TranslationsEqualSingleQueriesAtAnyThreadCount) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto starts = randomPoints(world.bounds(), kQueries, 1);
  const auto ends = randomPoints(world.bounds().expanded(64), kQueries, 2);
  TranslationBatch batch;
  batch.query.trm = &playerBox();
  batch.query.detectStartSolid = true;
  batch.starts = starts;
  batch.ends = ends;

  std::vector<TraceResult> loop(kQueries);
  QueryWork work;
  int hits = 0;
  for (std::size_t i = 0; i < kQueries; ++i) {
    loop[i] = translate(world, {&playerBox(), {}, starts[i], ends[i], contents::kMaskSolid, {}, true}, work);
    hits += loop[i].fraction < 1;
  }
  EXPECT_GT(hits, int(kQueries) / 4) << "the queries must hit something to compare anything";
  for (const auto& options : optionVariants()) {
    std::vector<TraceResult> out(kQueries);
    ASSERT_TRUE(translateBatch(world, batch, out, options).ok());
    EXPECT_EQ(allBits(out), allBits(loop)) << "threads " << options.threads << " chunk " << options.chunkSize;
  }
}

TEST(Batch, OneStartManyEnds) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const std::vector<Vec3> start{world.bounds().center()};
  const auto ends = randomPoints(world.bounds(), 500, 3);
  std::vector<TraceResult> out(ends.size());
  TranslationBatch batch;
  batch.starts = start;  // a point trace from one start
  batch.ends = ends;
  ASSERT_TRUE(translateBatch(world, batch, out, threadsAndChunk(2)).ok());
  QueryWork work;
  for (std::size_t i = 0; i < ends.size(); ++i)
    ASSERT_EQ(bits(out[i]),
              bits(translate(world, {nullptr, {}, start[0], ends[i], contents::kMaskSolid, {}}, work)))
        << i;
}

TEST(Batch, RotationsEqualSingleQueriesAtAnyThreadCount) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto starts = randomPoints(world.bounds(), 600, 4);
  std::vector<Rotation> rotations;
  for (std::size_t i = 0; i < starts.size(); ++i)
    rotations.emplace_back(starts[i] + Vec3{Real(i % 7), 3, 0}, Vec3{0, 0, 1}, Real(int(i % 360) - 180));
  const TraceModel bone = *TraceModel::bone(60, 12);
  RotationBatch batch;
  batch.query.trm = &bone;
  batch.starts = starts;
  batch.rotations = rotations;
  std::vector<TraceResult> loop(starts.size());
  QueryWork work;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    RotationQuery q;
    q.trm = &bone;
    q.start = starts[i];
    q.rotation = rotations[i];
    loop[i] = rotate(world, q, work);
  }
  for (const auto& options : optionVariants()) {
    std::vector<TraceResult> out(starts.size());
    ASSERT_TRUE(rotateBatch(world, batch, out, options).ok());
    EXPECT_EQ(allBits(out), allBits(loop)) << "threads " << options.threads;
  }
}

TEST(Batch, ContentsPointContentsAndContactsEqualSingleQueries) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto points = randomPoints(world.bounds(), kQueries, 5);
  QueryWork work;

  std::vector<ContentsResult> contentsLoop(points.size());
  std::vector<PointContentsResult> pointLoop(points.size());
  std::vector<ContactsResult> contactsLoop(points.size());
  int stuck = 0, inside = 0, touching = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    contentsLoop[i] = contentsTest(world, {&playerBox(), {}, points[i], contents::kMaskSolid, {}}, work);
    pointLoop[i] = pointContents(world, {points[i], {}}, work);
    contactsLoop[i] =
        contacts(world, {&playerBox(), {}, points[i], {0, 0, -1}, 32, contents::kMaskSolid, {}, 8, {}}, work);
    stuck += contentsLoop[i].contents != 0;
    inside += pointLoop[i].contents != 0;
    touching += !contactsLoop[i].contacts.empty();
  }
  EXPECT_GT(stuck, 100);
  EXPECT_GT(inside, 100);
  EXPECT_GT(touching, 30);

  ContentsBatch cb;
  cb.query.trm = &playerBox();
  cb.positions = points;
  const std::vector<Vec3> down{{0, 0, -1}};
  ContactsBatch kb;
  kb.query.trm = &playerBox();
  kb.query.depth = 32;
  kb.query.maxContacts = 8;
  kb.starts = points;
  kb.dirs = down;
  PointContentsBatch pb;
  pb.points = points;
  for (const auto& options : optionVariants()) {
    std::vector<ContentsResult> c(points.size());
    std::vector<PointContentsResult> p(points.size());
    std::vector<ContactsResult> k(points.size());
    ASSERT_TRUE(contentsBatch(world, cb, c, options).ok());
    ASSERT_TRUE(pointContentsBatch(world, pb, p, options).ok());
    ASSERT_TRUE(contactsBatch(world, kb, k, options).ok());
    EXPECT_EQ(allBits(c), allBits(contentsLoop)) << "threads " << options.threads;
    EXPECT_EQ(allBits(p), allBits(pointLoop)) << "threads " << options.threads;
    EXPECT_EQ(allBits(k), allBits(contactsLoop)) << "threads " << options.threads;
  }
}

TEST(Batch, ContactsAlongRotationsEqualSingleQueriesAtAnyThreadCount) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto starts = randomPoints(world.bounds(), 600, 6);
  std::vector<Rotation> rotations;
  for (std::size_t i = 0; i < starts.size(); ++i)
    // An arm of 40 (about z or y): turning 60-long bones sweep wide enough to meet walls and floors.
    rotations.emplace_back(starts[i] + Vec3{40, Real(i % 5), 0}, i % 2 ? Vec3{0, 0, 1} : Vec3{0, 1, 0},
                           Real(int(i % 360) - 180));
  const TraceModel bone = *TraceModel::bone(60, 12);
  ContactsBatch batch;
  batch.query.trm = &bone;
  batch.query.maxContacts = 8;
  batch.starts = starts;
  batch.rotations = rotations;  // dirs left empty: query.dir (zero) for every query
  std::vector<ContactsResult> loop(starts.size());
  QueryWork work;
  int touching = 0;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    ContactsQuery q = batch.query;
    q.start = starts[i];
    q.rotation = rotations[i];
    loop[i] = contacts(world, q, work);
    ASSERT_EQ(loop[i].status, QueryStatus::Ok);
    touching += !loop[i].contacts.empty();
  }
  EXPECT_GT(touching, 30);
  for (const auto& options : optionVariants()) {
    std::vector<ContactsResult> out(starts.size());
    ASSERT_TRUE(contactsBatch(world, batch, out, options).ok());
    EXPECT_EQ(allBits(out), allBits(loop)) << "threads " << options.threads;
  }

  // One rotation for all, in the query struct (no rotations span): the same
  // as the single queries with it.
  ContactsBatch shared = batch;
  shared.rotations = {};
  shared.query.rotation = rotations[7];
  const std::vector<Vec3> still{{0, 0, 0}};
  shared.dirs = still;
  std::vector<ContactsResult> out(starts.size());
  ASSERT_TRUE(contactsBatch(world, shared, out, threadsAndChunk(3, 7)).ok());
  for (std::size_t i = 0; i < starts.size(); ++i) {
    ContactsQuery q = shared.query;
    q.start = starts[i];
    EXPECT_EQ(bits(out[i]), bits(contacts(world, q, work))) << i;
  }

  // Dirs with a depth beside the rotations: every query refused.
  ContactsBatch mixed = batch;
  const std::vector<Vec3> east{{1, 0, 0}};
  mixed.dirs = east;
  mixed.query.depth = 8;
  ASSERT_TRUE(contactsBatch(world, mixed, out, threadsAndChunk(2)).ok());
  for (const ContactsResult& r : out) {
    EXPECT_EQ(r.status, QueryStatus::MixedMotion);
    EXPECT_TRUE(r.contacts.empty());
  }
}

// A batch holds the single query's struct: its shared fields (here a mask,
// a turned and moved placement, a turned trace model) reach every query,
// and the fields the spans give (start, end, position, point, dir) are
// ignored, even when they hold NaN.
TEST(Batch, TheQueryStructOfABatchIsTheSingleQuerysWithTheSpansFieldsIgnored) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto starts = randomPoints(world.bounds(), 400, 11);
  const auto ends = randomPoints(world.bounds(), 400, 12);
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  Placement turned;
  turned.origin = {8, -4, 2};
  turned.axis = Rotation({0, 0, 0}, {0, 0, 1}, 30).matrix();
  TranslationQuery tq;
  tq.trm = &playerBox();
  tq.trmAxis = Rotation({0, 0, 0}, {0, 0, 1}, 45).matrix();
  tq.contentMask = contents::kMaskPlayerSolid;
  tq.placement = turned;
  tq.detectStartSolid = true;
  TranslationBatch tb{tq, starts, ends};
  tb.query.start = tb.query.end = {nan, nan, nan};
  ContentsQuery cq{&playerBox(), tq.trmAxis, {nan, nan, nan}, contents::kMaskPlayerSolid, turned};
  const ContentsBatch cb{cq, starts};
  ContactsQuery kq;
  kq.trm = &playerBox();
  kq.start = kq.dir = {nan, nan, nan};
  kq.depth = 24;
  kq.maxContacts = 5;
  kq.placement = turned;
  const std::vector<Vec3> down{{0, 0, -1}};
  const ContactsBatch kb{kq, starts, down, {}};
  const PointContentsBatch pb{{{nan, nan, nan}, turned}, starts};
  RayBatch rb{{{nan, nan, nan}, {nan, nan, nan}, contents::kMaskPlayerSolid, turned}, starts, ends};

  std::vector<TraceResult> t(starts.size()), tLoop(starts.size());
  std::vector<ContentsResult> c(starts.size()), cLoop(starts.size());
  std::vector<ContactsResult> k(starts.size()), kLoop(starts.size());
  std::vector<PointContentsResult> p(starts.size()), pLoop(starts.size());
  std::vector<RayHit> h(starts.size()), hLoop(starts.size());
  const RayIndex index(world);
  QueryWork work;
  int stuck = 0;
  for (std::size_t i = 0; i < starts.size(); ++i) {
    TranslationQuery q = tq;
    q.start = starts[i];
    q.end = ends[i];
    tLoop[i] = translate(world, q, work);
    ContentsQuery qc = cq;
    qc.position = starts[i];
    cLoop[i] = contentsTest(world, qc, work);
    stuck += cLoop[i].contents != 0;
    ContactsQuery qk = kq;
    qk.start = starts[i];
    qk.dir = {0, 0, -1};
    kLoop[i] = contacts(world, qk, work);
    pLoop[i] = pointContents(world, {starts[i], turned}, work);
    hLoop[i] = index.cast({starts[i], ends[i], contents::kMaskPlayerSolid, turned});
    ASSERT_EQ(tLoop[i].status, QueryStatus::Ok) << i;
  }
  EXPECT_GT(stuck, 10) << "the queries must meet something to compare anything";
  const BatchOptions options = threadsAndChunk(2, 7);
  ASSERT_TRUE(translateBatch(world, tb, t, options).ok());
  ASSERT_TRUE(contentsBatch(world, cb, c, options).ok());
  ASSERT_TRUE(contactsBatch(world, kb, k, options).ok());
  ASSERT_TRUE(pointContentsBatch(world, pb, p, options).ok());
  ASSERT_TRUE(castRayBatch(index, rb, h, options).ok());
  EXPECT_EQ(allBits(t), allBits(tLoop));
  EXPECT_EQ(allBits(c), allBits(cLoop));
  EXPECT_EQ(allBits(k), allBits(kLoop));
  EXPECT_EQ(allBits(p), allBits(pLoop));
  EXPECT_EQ(allBits(h), allBits(hLoop));
  std::vector<RayHit> many(starts.size());
  index.castMany(rb, many);
  EXPECT_EQ(allBits(many), allBits(hLoop));
}

// A refused query in a batch is refused alone, with its status.
TEST(Batch, ARefusedPointHasItsStatusInTheBatch) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const Real nan = std::numeric_limits<Real>::quiet_NaN();
  const std::vector<Vec3> points{world.bounds().center(), {nan, 0, 0}, {0, 0, 2e9f}};
  std::vector<PointContentsResult> out(points.size());
  ASSERT_TRUE(pointContentsBatch(world, {{}, points}, out).ok());
  EXPECT_EQ(out[0].status, QueryStatus::Ok);
  EXPECT_EQ(out[1].status, QueryStatus::NonFinite);
  EXPECT_EQ(out[1].contents, 0u);
  EXPECT_EQ(out[2].status, QueryStatus::OutOfRange);
  EXPECT_EQ(out[2].contents, 0u);
}

TEST(Batch, RayCastsEqualSingleCasts) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const RayIndex index(world);
  const auto starts = randomPoints(world.bounds(), kQueries, 6);
  const auto ends = randomPoints(world.bounds(), kQueries, 7);
  std::vector<RayHit> loop(kQueries);
  int hits = 0;
  for (std::size_t i = 0; i < kQueries; ++i) {
    loop[i] = index.cast({starts[i], ends[i], contents::kMaskSolid, {}});
    hits += loop[i].hit();
  }
  EXPECT_GT(hits, int(kQueries) / 4);
  RayBatch batch;
  batch.starts = starts;
  batch.ends = ends;
  for (const auto& options : optionVariants()) {
    std::vector<RayHit> out(kQueries);
    ASSERT_TRUE(castRayBatch(index, batch, out, options).ok());
    EXPECT_EQ(allBits(out), allBits(loop)) << "threads " << options.threads;
  }
}

TEST(Batch, ProgressCountsUpToTheBatchSize) {
  ASSERT_FALSE(lt4().empty());
  const auto points = randomPoints(lt4()[0]->bounds(), 1000, 8);
  std::vector<PointContentsResult> out(points.size());
  std::vector<std::size_t> seen;
  BatchOptions options = threadsAndChunk(1, 100);
  options.progress = [&](std::size_t done, std::size_t total) {
    EXPECT_EQ(total, points.size());
    seen.push_back(done);
    return true;
  };
  ASSERT_TRUE(pointContentsBatch(*lt4()[0], {{}, points}, out, options).ok());
  // One thread: after each of the 10 chunks, then once at the end.
  const std::vector<std::size_t> expected{100, 200, 300, 400, 500, 600, 700, 800, 900, 1000, 1000};
  EXPECT_EQ(seen, expected);
}

TEST(Batch, CancelStopsTheBatch) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const auto starts = randomPoints(world.bounds(), 1000, 9);
  TranslationBatch batch;
  batch.query.trm = &playerBox();
  batch.starts = starts;
  batch.ends = starts;  // position tests
  std::vector<TraceResult> out(starts.size());
  for (auto& r : out) r.fraction = -7;  // untouched marker
  int calls = 0;
  BatchOptions options = threadsAndChunk(1, 10);
  options.progress = [&](std::size_t, std::size_t) { return ++calls < 3; };
  const Status s = translateBatch(world, batch, out, options);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "batch cancelled after 30 of 1000 queries");
  EXPECT_EQ(calls, 3);
  for (std::size_t i = 0; i < 30; ++i) EXPECT_NE(out[i].fraction, -7) << i;
  for (std::size_t i = 30; i < out.size(); ++i) ASSERT_EQ(out[i].fraction, -7) << "query " << i << " ran";

  // On several threads a cancel stops the batch as well (how many queries
  // ran before the workers saw it is up to the threads): the first report
  // cancels, wherever it comes from (a chunk of the calling thread, a
  // helper's progress, the final report).
  calls = 0;
  options.threads = 4;
  options.progress = [&](std::size_t, std::size_t) { return ++calls < 1; };
  const Status stopped = translateBatch(world, batch, out, options);
  ASSERT_FALSE(stopped.ok());
  EXPECT_NE(stopped.error().message.find("batch cancelled after"), std::string::npos)
      << stopped.error().message;
  EXPECT_EQ(calls, 1);
}

TEST(Batch, ProgressHookExceptionIsAnError) {
  ASSERT_FALSE(lt4().empty());
  const std::vector<Vec3> points(50);
  std::vector<PointContentsResult> out(points.size());
  BatchOptions options = threadsAndChunk(2, 5);
  options.progress = [](std::size_t, std::size_t) -> bool { throw std::runtime_error("hook broke"); };
  const Status s = pointContentsBatch(*lt4()[0], {{}, points}, out, options);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error().message, "the batch progress hook failed: hook broke");
}

TEST(Batch, EmptyBatchesSucceedAndCallNothing) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  bool called = false;
  BatchOptions options;
  options.progress = [&](std::size_t, std::size_t) { return called = true; };
  const std::vector<Vec3> one{{0, 0, 0}};
  EXPECT_TRUE(translateBatch(world, {}, {}, options).ok());
  TranslationBatch oneStartNoEnds;
  oneStartNoEnds.starts = one;  // one start, zero ends: zero queries
  EXPECT_TRUE(translateBatch(world, oneStartNoEnds, {}, options).ok());
  EXPECT_TRUE(rotateBatch(world, {}, {}, options).ok());
  EXPECT_TRUE(contentsBatch(world, {}, {}, options).ok());
  EXPECT_TRUE(contactsBatch(world, {}, {}, options).ok());
  EXPECT_TRUE(pointContentsBatch(world, {}, {}, options).ok());
  EXPECT_TRUE(castRayBatch(RayIndex(world), {}, {}, options).ok());
  EXPECT_FALSE(called);
}

TEST(Batch, InputsOfTheWrongLengthAreRefused) {
  ASSERT_FALSE(lt4().empty());
  const CollisionModel& world = *lt4()[0];
  const std::vector<Vec3> three(3), two(2);
  std::vector<TraceResult> out3(3), out2(2);
  for (auto& r : out3) r.fraction = -7;
  TranslationBatch t;
  t.starts = three;
  t.ends = two;
  const Status mismatch = translateBatch(world, t, out3);
  ASSERT_FALSE(mismatch.ok());
  EXPECT_EQ(mismatch.error().message,
            "batch inputs of different lengths: starts and ends (3 and 2; each must be 1 or the batch size)");
  t.ends = three;
  const Status wrongOut = translateBatch(world, t, out2);
  ASSERT_FALSE(wrongOut.ok());
  EXPECT_EQ(wrongOut.error().message, "batch output holds 2 results for 3 queries");
  for (const auto& r : out3) EXPECT_EQ(r.fraction, -7) << "nothing is computed for a refused batch";

  RotationBatch r;
  r.starts = three;
  const std::vector<Rotation> rotations(2);
  r.rotations = rotations;
  EXPECT_FALSE(rotateBatch(world, r, out3).ok());
  std::vector<ContentsResult> c2(2);
  ContentsBatch cb;
  cb.positions = three;
  EXPECT_FALSE(contentsBatch(world, cb, c2).ok());
  std::vector<ContactsResult> k3(3);
  ContactsBatch kb;
  kb.starts = three;
  kb.dirs = two;
  EXPECT_FALSE(contactsBatch(world, kb, k3).ok());
  kb.dirs = {};
  kb.rotations = rotations;  // 2 rotations for 3 starts
  const Status turns = contactsBatch(world, kb, k3);
  ASSERT_FALSE(turns.ok());
  EXPECT_EQ(turns.error().message,
            "batch inputs of different lengths: starts, dirs and rotations (3 and 2; each "
            "must be 1 or the batch size)");
  kb.starts = two;
  EXPECT_FALSE(contactsBatch(world, kb, k3).ok()) << "an out span of the wrong length";
  kb.dirs = three;
  EXPECT_FALSE(contactsBatch(world, kb, k3).ok()) << "3 dirs, 2 starts";
  std::vector<PointContentsResult> p2(2);
  EXPECT_FALSE(pointContentsBatch(world, {{}, three}, p2).ok());
  std::vector<RayHit> h3(3);
  RayBatch rb;
  rb.starts = two;
  rb.ends = three;
  EXPECT_FALSE(castRayBatch(RayIndex(world), rb, h3).ok());
}
