// Agreement with the original implementation: every query file in
// ../shared/reference (skipped without it) is answered and compared with the
// original's results by the rules tests/fidelity/check_lt4.py states. Where the original is known to be wrong
// (shared/reference/README.md), the difference must be explained by an
// independent re-implementation of the original's mistake.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "cmkit/cm_file.h"
#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "cmkit/tools/query_format.h"
#include "test_support.h"

using namespace cmkit;
namespace fs = std::filesystem;

namespace {

using detail::Fields;
using test::numbers;

bool close(std::string_view a, std::string_view b, double eps) {
  const auto x = numbers(a), y = numbers(b);
  if (x.size() != y.size() || x.empty()) return false;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!(std::fabs(double(x[i]) - double(y[i])) <= eps)) return false;
  return true;
}

// agree.py's verdict: "agree", "tie?" or a reason.
std::string judge(const std::string& op, const Fields& ref, const Fields& got) {
  if (ref.has("error") || got.has("error")) return ref.has("error") && got.has("error") ? "agree" : "error";
  if (op == "pointcontents") return ref.value("contents") == got.value("contents") ? "agree" : "contents";
  if (op == "contacts") return ref.value("count") == got.value("count") ? "agree" : "count";
  if (!close(ref.value("fraction"), got.value("fraction"), 1e-4)) return "fraction";
  if (!close(ref.value("endpos"), got.value("endpos"), 1e-2)) return "endpos";
  if (op == "contents" && ref.value("result") != got.value("result")) return "result";
  if (numbers(ref.value("fraction"))[0] < 1 && !close(ref.value("normal"), got.value("normal"), 1e-3))
    return "tie?";
  return "agree";
}

bool refusedByOriginal(const std::string& op, const Fields& q) {
  if (op != "translation" || q.value("trm") == "point") return false;
  const auto s = numbers(q.value("start")), e = numbers(q.value("end"));
  return std::hypot(s[0] - e[0], s[1] - e[1], s[2] - e[2]) > 4096.0;
}

// The original's PointContents, reproduced independently with its two
// mistakes: only the leaf's brushes are looked at, and the model axis is
// applied the wrong way round (row vector times axis, not axis times vector).
std::uint32_t originalPointContents(const CollisionModel& m, const Fields& q, const std::string& posKey) {
  const auto pos = numbers(q.value(posKey));
  double p[3] = {pos[0], pos[1], pos[2]};
  if (q.has("origin")) {
    const auto o = numbers(q.value("origin"));
    for (int i = 0; i < 3; ++i) p[i] -= o[i];
  }
  float fp[3] = {float(p[0]), float(p[1]), float(p[2])};
  if (q.has("modelaxis")) {
    const auto a = numbers(q.value("modelaxis"));
    float r[3];
    for (int j = 0; j < 3; ++j)
      r[j] = fp[0] * float(a[0 + j]) + fp[1] * float(a[3 + j]) + fp[2] * float(a[6 + j]);
    for (int j = 0; j < 3; ++j) fp[j] = r[j];
  }
  std::size_t n = 0;
  while (m.nodes()[n].planeType >= 0)
    n = std::size_t(m.nodes()[n].children[fp[m.nodes()[n].planeType] > m.nodes()[n].planeDist ? 0 : 1]);
  for (std::int32_t b : m.brushesAt(m.nodes()[n])) {
    const CmBrush& brush = m.brushes()[std::size_t(b)];
    bool inside = true;
    for (int i = 0; i < 3 && inside; ++i)
      inside = fp[i] >= brush.bounds.min[i] && fp[i] <= brush.bounds.max[i];
    for (const Plane& pl : m.planesOf(brush))
      inside = inside && pl.normal.x * fp[0] + pl.normal.y * fp[1] + pl.normal.z * fp[2] - pl.dist < 0;
    if (inside) return brush.contents;
  }
  return 0;
}

const CollisionModel& modelFor(const std::vector<ModelPtr>& models, const Fields& q) {
  if (!q.has("model")) return *models[0];
  const std::string_view name = q.value("model");
  if (name[0] == '#') return *models[std::size_t(detail::parseInt(name.substr(1)).value_or(0))];
  for (const auto& m : models)
    if (m->name() == name) return *m;
  return *models[0];
}

struct Tally {
  int lines = 0, agree = 0, tie = 0, explained = 0;
  std::vector<std::string> examples;
};

// Loads the models the reference results were made from.
std::vector<ModelPtr> referenceModels(const std::string& name) {
  const fs::path maps = test::sharedDir() / "maps";
  const fs::path cm = maps / "rbdoom-unittests" / (name + ".cm");
  if (fs::exists(cm)) {  // the reference ran these .cm files directly
    auto file = loadCmFile(cm.string(), MaterialTable{});
    EXPECT_TRUE(file.ok()) << (file.ok() ? "" : file.error().toString());
    return file.ok() ? file->models : std::vector<ModelPtr>{};
  }
  for (const auto& dir : fs::directory_iterator(maps)) {
    const fs::path map = dir.path() / (name + ".map");
    if (!fs::exists(map)) continue;
    return test::buildMapModels(map);
  }
  ADD_FAILURE() << "no map or .cm for reference " << name;
  return {};
}

}  // namespace

TEST(Agreement, TranslationContentsContactsAndPointContentsMatchTheOriginal) {
  CMKIT_FLOAT_BUILD_ONLY();
  CMKIT_REQUIRE_SHARED(
      "the original's reference queries and answers, reference/*.queries.txt and *.results.txt: about 700 KB "
      "per map, not bundled to keep the repository small, and some made from the GPL-2.0+ darkradiant maps, "
      "whose licence does not allow bundling them; data/reference/lt4 is the bundled slice (ctest "
      "fidelity_lt4_slice)");
  std::map<std::string, Tally> total;
  // reference-proc: maps with a .proc beside them, built with it (referenceModels)
  std::vector<std::pair<std::string, fs::directory_entry>> queryFiles;
  for (const char* dir : {"reference", "reference-proc"})
    for (const auto& entry : fs::directory_iterator(test::sharedDir() / dir))
      queryFiles.emplace_back(dir, entry);
  for (const auto& [refDir, entry] : queryFiles) {
    const std::string file = entry.path().filename().string();
    if (file.size() < 12 || file.substr(file.size() - 12) != ".queries.txt") continue;
    const std::string name = file.substr(0, file.size() - 12);
    SCOPED_TRACE(name);
    const std::vector<ModelPtr> models = referenceModels(name);
    ASSERT_FALSE(models.empty());
    std::istringstream queries(test::readFile(entry.path()));
    std::istringstream results(test::readFile(test::sharedDir() / refDir / (name + ".results.txt")));
    QueryWork work;
    std::map<std::string, Tally> tally;
    for (std::string q; std::getline(queries, q);) {
      if (!isQueryLine(q)) continue;
      std::string refLine;
      std::getline(results, refLine);
      const std::string op = q.substr(0, q.find(' '));
      if (op == "rotation") continue;  // judged by the rotation tests
      const Fields qf(q);
      if (refusedByOriginal(op, qf)) continue;
      const std::string got = answerQueryLine(models, q, work);
      const Fields ref(refLine), ours(got);
      Tally& t = tally[op];
      ++t.lines;
      const std::string verdict = judge(op, ref, ours);
      if (verdict == "agree") {
        ++t.agree;
        continue;
      }
      if (verdict == "tie?") {
        ++t.tie;
        continue;
      }
      // Point contents (pointcontents lines, and contents with a point) go
      // through the original's PointContents: a difference is explained when
      // the original's algorithm, mistakes included, gives the reference.
      const bool pointQuery = op == "pointcontents" || (op == "contents" && qf.value("trm") == "point");
      if (pointQuery && !ref.has("error")) {
        const std::uint32_t original =
            originalPointContents(modelFor(models, qf), qf, op == "pointcontents" ? "pos" : "start");
        const std::string key = op == "pointcontents" ? "contents" : "result";
        if (std::to_string(original) == ref.value(key)) {
          ++t.explained;
          continue;
        }
      }
      if (t.examples.size() < 3)
        t.examples.push_back(verdict + ": " + q + "\n  ref:  " + refLine + "\n  ours: " + got);
    }
    for (auto& [op, t] : tally) {
      Tally& all = total[op];
      all.lines += t.lines;
      all.agree += t.agree;
      all.tie += t.tie;
      all.explained += t.explained;
      const double rate = 100.0 * (t.agree + t.tie + t.explained) / std::max(1, t.lines);
      EXPECT_GE(rate, 99.0) << op << " on " << name;
      for (const auto& ex : t.examples) std::cout << "[" << name << "] " << ex << "\n";
    }
  }
  for (const auto& [op, t] : total) {
    const double rate = 100.0 * (t.agree + t.tie + t.explained) / std::max(1, t.lines);
    std::cout << op << ": " << t.lines << " lines, agree " << t.agree << ", tie? " << t.tie
              << ", original's documented bug " << t.explained << " -> " << rate << "%\n";
    EXPECT_GE(rate, 99.5) << op << " over all reference maps";
  }
}
