// Rotations on the shared maps: properties (free starts end free, end axes
// orthonormal, everything finite) and agreement with the original's results,
// with every rotation where the original went further than cmkit checked
// independently by sampling the rotation with position tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <random>
#include <sstream>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/query.h"
#include "cmkit/tools/query_format.h"
#include "test_support.h"

using namespace cmkit;

namespace {

std::vector<ModelPtr> buildMap(const std::filesystem::path& path) {
  auto map = loadMapFile(path.string());
  if (!map) return {};
  auto models = buildCollisionModels(*map, MaterialTable{});
  return models ? models->models : std::vector<ModelPtr>{};
}

using detail::Fields;
using test::numbers;

std::string vecText(const Vec3& v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.9g,%.9g,%.9g", double(v.x), double(v.y), double(v.z));
  return buf;
}

// The first sampled fraction in [0, upTo] (n + 1 poses) at which the trace
// model of a rotation line overlaps something; -1 if none.
float firstOverlap(std::span<const ModelPtr> models, const std::string& query, float upTo, int n,
                   QueryWork& work) {
  const Fields f(query);
  const auto o = numbers(f.value("rotorigin")), a = numbers(f.value("rotaxis")),
             s = numbers(f.value("start"));
  const float angle = numbers(f.value("angle")).at(0);
  Mat3 trmAxis;
  if (f.has("trmaxis")) {
    const auto m = numbers(f.value("trmaxis"));
    trmAxis = Mat3{{m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]}};
  }
  std::string keep;
  for (const char* k : {"trm", "mask", "model", "origin", "modelaxis"})
    if (f.has(k)) keep += std::string(" ") + k + "=" + std::string(f.value(k));
  for (int k = 0; k <= n; ++k) {
    const float frac = upTo * float(k) / float(n);
    const Rotation r({o[0], o[1], o[2]}, {a[0], a[1], a[2]}, angle * frac);
    const Mat3 axis = r.rotateAxis(trmAxis);
    std::string line = "contents" + keep + " start=" + vecText(r.rotatePoint({s[0], s[1], s[2]})) +
                       " trmaxis=" + vecText(axis[0]) + "," + vecText(axis[1]) + "," + vecText(axis[2]);
    const std::string result = answerQueryLine(models, line, work);
    const Fields res(result);
    if (res.has("result") && res.value("result") != "0") return frac;
  }
  return -1;
}

// The trace-model spec of a query line with its bounds grown by `grow`
// ("box:x0,y0,z0,x1,y1,z1", "cylinder:N:..." and the other kinds given by
// bounds); empty for other specs.
std::string grownTrm(std::string_view spec, float grow) {
  const std::size_t numbersAt = spec.rfind(':') + 1;
  const auto b = numbers(spec.substr(numbersAt));
  if (numbersAt == 0 || b.size() != 6) return {};
  std::string out(spec.substr(0, numbersAt));
  for (int i = 0; i < 6; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.9g", i ? "," : "",
                  double(b[std::size_t(i)] + (i < 3 ? -grow : grow)));
    out += buf;
  }
  return out;
}

// Whether the trace model of a rotation line, at the pose of its answer,
// grown by `grow` on every side, overlaps something: a stop at the clip band
// of a surface (within the clip epsilon of an edge, along the edge's normal,
// which for a right-angled edge is 0.25 * sqrt(2) away).
bool nearSomethingAtStop(std::span<const ModelPtr> models, const std::string& query, const Fields& answer,
                         float grow, QueryWork& work) {
  const Fields f(query);
  const std::string trm = grownTrm(f.value("trm"), grow);
  if (trm.empty()) return false;
  std::string line = "contents trm=" + trm + " start=" + std::string(answer.value("endpos")) +
                     " trmaxis=" + std::string(answer.value("endaxis"));
  for (const char* k : {"mask", "model", "origin", "modelaxis"})
    if (f.has(k)) line += std::string(" ") + k + "=" + std::string(f.value(k));
  const std::string result = answerQueryLine(models, line, work);
  const Fields res(result);
  return res.has("result") && res.value("result") != "0";
}

}  // namespace

TEST(RotationShared, FreeStartsEndFreeWithOrthonormalAxes) {
  const std::vector<TraceModel> trms = {*TraceModel::box({{-16, -16, 0}, {16, 16, 72}}),
                                        *TraceModel::cylinder({{-12, -12, -20}, {12, 12, 20}}, 8),
                                        *TraceModel::octahedron({{-10, -10, -10}, {10, 10, 10}}),
                                        *TraceModel::bone(40, 12),
                                        *TraceModel::dodecahedron({{-9, -9, -9}, {9, 9, 9}})};
  QueryWork work;
  // OPEN ISSUE: a few free starts still end overlapping, all on altar's
  // patches: with seed 11, 10 of 1200 in the GCC build, 13 in the Clang
  // build (its rounding picks other starts); 15 in the GCC build before a
  // trace-model edge that passes a model edge's line beyond its end was
  // tested for its second crossing. The original's weakness that cmkit has
  // not fixed yet; guarded so that it cannot get worse than it was.
  int endInSolid = 0;
  for (const char* name : {"synthetic/box_room.map", "darkradiant-altar/altar.map", "lt4/lt4.map"}) {
    const auto path = test::dataFile(std::string("maps/") + name);
    if (!std::filesystem::exists(path)) {
      std::printf("note: %s left out: %s\n", name, test::whyNotBundled(name).c_str());
      continue;
    }
    const auto models = buildMap(path);
    ASSERT_FALSE(models.empty()) << name;
    const CollisionModel& m = *models[0];
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0, 1), ang(-400, 400), unit(-1, 1);
    int tested = 0, hits = 0;
    for (int n = 0; n < 3000 && tested < 400; ++n) {
      RotationQuery q;
      q.trm = n % 6 == 5 ? nullptr : &trms[std::size_t(n % 5)];
      const Vec3 lo = m.bounds().min, size = m.bounds().size();
      q.start = {lo.x + u(rng) * size.x, lo.y + u(rng) * size.y, lo.z + u(rng) * size.z};
      ContentsQuery cq{q.trm, q.trmAxis, q.start, q.contentMask, q.placement};
      if (contentsTest(m, cq, work).contents != 0) continue;
      Vec3 axis{unit(rng), unit(rng), unit(rng)};
      if (n % 2) axis = {0, 0, unit(rng) < 0 ? -1.0f : 1.0f};
      if (axis.normalize() == 0) continue;
      q.rotation = Rotation(q.start + Vec3{unit(rng), unit(rng), unit(rng)} * 60, axis, ang(rng));
      const TraceResult r = rotate(m, q, work);
      ++tested;
      hits += r.fraction < 1;
      ASSERT_TRUE(std::isfinite(r.fraction) && r.endPos.isFinite() && r.endAxis.isFinite() &&
                  r.contact.point.isFinite() && r.contact.normal.isFinite() && std::isfinite(r.contact.dist))
          << name << " query " << n;
      EXPECT_GE(r.fraction, 0.0f);
      EXPECT_LE(r.fraction, 1.0f);
      EXPECT_LT(r.endAxis.orthonormalityError(), 1e-4f);
      ContentsQuery end{q.trm, r.endAxis, r.endPos, q.contentMask, q.placement};
      if (contentsTest(m, end, work).contents != 0) {
        ++endInSolid;
        std::printf("%s query %d: free start, fraction %.6f, end pose in solid\n", name, n,
                    double(r.fraction));
      }
    }
    EXPECT_GT(tested, 200) << name;
    EXPECT_GT(hits, 20) << name;
  }
  EXPECT_LE(endInSolid, 16);
}

// Agreement on the reference rotation lines (agree or tie, as
// tools/agree.py counts), and every line where the original turned further
// than cmkit checked by sampling: either the start overlaps already (both
// answers are the original's start-in-solid rules) or the original turned
// into solid (its miss). The counts go to docs/fidelity.md.
TEST(RotationShared, AgreesWithTheOriginalAndItsMissesAreConfirmed) {
  CMKIT_FLOAT_BUILD_ONLY();
  CMKIT_REQUIRE_SHARED(
      "the original's reference queries and answers, reference/*.queries.txt and *.results.txt: about 700 KB "
      "per map, not bundled to keep the repository small, and some made from the GPL-2.0+ darkradiant maps, "
      "whose licence does not allow bundling them");
  const auto refDir = test::sharedDir() / "reference";
  int allLines = 0, allOk = 0, confirmedMisses = 0, startSolid = 0, bandStops = 0, unexplained = 0;
  // A stop counts as one at the clip band when the trace model grown by this
  // much overlaps something there: the band is the clip epsilon (0.25) out
  // along an edge's normal, up to 0.25 * sqrt(2) from a right-angled edge.
  constexpr float kClipBandSlack = 0.4f;
  QueryWork work;
  for (const auto& entry : std::filesystem::directory_iterator(refDir)) {
    const std::string file = entry.path().filename().string();
    if (file.size() < 12 || file.substr(file.size() - 12) != ".queries.txt") continue;
    const std::string name = file.substr(0, file.size() - 12);
    std::vector<ModelPtr> models;
    const auto cm = test::sharedDir() / "maps/rbdoom-unittests" / (name + ".cm");
    if (std::filesystem::exists(cm)) {
      auto loaded = loadCmFile(cm.string(), MaterialTable{});
      if (loaded) models = loaded->models;
    } else {
      for (const auto& dir : std::filesystem::directory_iterator(test::sharedDir() / "maps")) {
        const auto p = dir.path() / (name + ".map");
        if (std::filesystem::exists(p)) models = buildMap(p);
      }
    }
    ASSERT_FALSE(models.empty()) << name;
    std::istringstream queries(test::readFile(entry.path()));
    std::istringstream results(test::readFile(refDir / (name + ".results.txt")));
    int lines = 0, ok = 0;
    for (std::string q; std::getline(queries, q);) {
      if (!isQueryLine(q)) continue;
      std::string refLine;
      std::getline(results, refLine);
      if (q.rfind("rotation ", 0) != 0) continue;
      const std::string got = answerQueryLine(models, q, work);
      const Fields ref(refLine), mine(got);
      ++lines;
      if (ref.has("error") || mine.has("error")) {
        ok += ref.has("error") && mine.has("error");
        continue;
      }
      const float fr = numbers(ref.value("fraction")).at(0);
      const float fg = numbers(mine.value("fraction")).at(0);
      const auto pr = numbers(ref.value("endpos")), pg = numbers(mine.value("endpos"));
      bool same = std::fabs(fr - fg) <= 1e-4f;
      for (int i = 0; i < 3 && same; ++i) same = std::fabs(pr[size_t(i)] - pg[size_t(i)]) <= 1e-2f;
      if (same) {
        ++ok;
        continue;
      }
      if (!(fr > fg)) continue;  // cmkit turned further: see docs/fidelity.md
      const float hit = firstOverlap(models, q, fr, 200, work);
      if (hit == 0)
        ++startSolid;
      else if (hit > 0)
        ++confirmedMisses;
      else if (nearSomethingAtStop(models, q, mine, kClipBandSlack, work))
        ++bandStops;  // the original passed within the clip band of an edge; cmkit stopped there
      else {
        ++unexplained;
        ADD_FAILURE() << name << ": cmkit stops at " << fg << " before the original (" << fr
                      << ") with no overlap found, nor anything within its clip band: " << q;
      }
    }
    EXPECT_GE(100.0 * ok / lines, 98.0) << name;
    allLines += lines;
    allOk += ok;
  }
  std::printf(
      "rotation lines %d, agree or tie %d (%.2f%%); original turned further: %d start in solid, %d "
      "confirmed misses of the original, %d stops at the clip band of an edge the original passed, %d "
      "unexplained\n",
      allLines, allOk, 100.0 * allOk / allLines, startSolid, confirmedMisses, bandStops, unexplained);
  EXPECT_GE(100.0 * allOk / allLines, 99.0);
  EXPECT_EQ(unexplained, 0);
}
