// Patch tessellation for collision, on hand-computed patches and against
// the patch vertices of the reference .cm files.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>

#include "cmkit/map.h"
#include "geometry/patch.h"
#include "test_support.h"

namespace {

using cmkit::MapPatch;
using cmkit::Vec3;
using cmkit::detail::PatchGrid;
using cmkit::detail::subdividePatchForCollision;

/// A patch from columns (file groups) of points: cols[j][i] -> i*width+j.
MapPatch patchFromColumns(const std::vector<std::vector<Vec3>>& cols) {
  MapPatch p;
  p.material = "m";
  p.width = static_cast<int>(cols.size());
  p.height = static_cast<int>(cols[0].size());
  p.points.resize(cols.size() * cols[0].size());
  for (int j = 0; j < p.width; ++j) {
    for (int i = 0; i < p.height; ++i) p.points[static_cast<std::size_t>(i * p.width + j)] = cols[j][i];
  }
  return p;
}

Vec3 at(const PatchGrid& g, int column, int row) {
  return g.points[static_cast<std::size_t>(row * g.width + column)];
}

/// A quarter cylinder of radius r around the z axis (from (r,0) to (0,r)),
/// 128 high: columns are the arc's control points, rows are heights.
MapPatch quarterCylinder(float r) {
  auto column = [](float x, float y) { return std::vector<Vec3>{{x, y, 0}, {x, y, 64}, {x, y, 128}}; };
  return patchFromColumns({column(r, 0), column(r, r), column(0, r)});
}

/// The quadratic Bézier of the quarter cylinder's arc at t.
Vec3 arc(float r, float t) {
  const float s = 1 - t;
  return {s * s * r + 2 * t * s * r, 2 * t * s * r + t * t * r, 0};
}

TEST(Patch, FlatThreeByThreeBecomesTwoByTwo) {
  const MapPatch flat = patchFromColumns({{{0, 0, 0}, {0, 32, 0}, {0, 64, 0}},
                                          {{32, 0, 0}, {32, 32, 0}, {32, 64, 0}},
                                          {{64, 0, 0}, {64, 32, 0}, {64, 64, 0}}});
  const PatchGrid g = subdividePatchForCollision(flat);
  ASSERT_EQ(g.width, 2);
  ASSERT_EQ(g.height, 2);
  ASSERT_EQ(g.points.size(), 4u);
  EXPECT_EQ(at(g, 0, 0), (Vec3{0, 0, 0}));
  EXPECT_EQ(at(g, 1, 0), (Vec3{64, 0, 0}));
  EXPECT_EQ(at(g, 0, 1), (Vec3{0, 64, 0}));
  EXPECT_EQ(at(g, 1, 1), (Vec3{64, 64, 0}));
}

TEST(Patch, QuarterCylinderSubdividesUntilTheErrorIsBelow24) {
  // The middle control point is |2b - a - c| / 4 = r * sqrt(2) / 4 from the
  // curve; each de Casteljau split divides that by 4. The straight rows
  // (along z) collapse to 2.
  struct Case {
    float radius;
    int columns;  // r=64: 22.6 (no split); 128: 45 -> 11; 256: 90 -> 23; 1024: 362 -> 90 -> 23
  };
  for (const Case c : {Case{64, 3}, Case{128, 5}, Case{256, 5}, Case{1024, 9}}) {
    SCOPED_TRACE(c.radius);
    const PatchGrid g = subdividePatchForCollision(quarterCylinder(c.radius));
    ASSERT_EQ(g.width, c.columns);
    ASSERT_EQ(g.height, 2);
    for (int j = 0; j < g.width; ++j) {
      // Every point is on the curve (dyadic parameters: exact in float).
      const Vec3 expected = arc(c.radius, static_cast<float>(j) / static_cast<float>(g.width - 1));
      EXPECT_EQ(at(g, j, 0), (Vec3{expected.x, expected.y, 0})) << "column " << j;
      EXPECT_EQ(at(g, j, 1), (Vec3{expected.x, expected.y, 128})) << "column " << j;
    }
  }
  // r = 256 by hand: B(1/4) = (240, 112), B(1/2) = (192, 192).
  const PatchGrid g = subdividePatchForCollision(quarterCylinder(256));
  EXPECT_EQ(at(g, 1, 0), (Vec3{240, 112, 0}));
  EXPECT_EQ(at(g, 2, 0), (Vec3{192, 192, 0}));
  EXPECT_EQ(at(g, 3, 1), (Vec3{112, 240, 128}));
}

TEST(Patch, CurvedAlongTheHeightToo) {
  // The arc runs along the rows (second index) instead.
  const float r = 256;
  const MapPatch p = patchFromColumns({{{r, 0, 0}, {r, r, 0}, {0, r, 0}},
                                       {{r, 0, 64}, {r, r, 64}, {0, r, 64}},
                                       {{r, 0, 128}, {r, r, 128}, {0, r, 128}}});
  const PatchGrid g = subdividePatchForCollision(p);
  ASSERT_EQ(g.width, 2);
  ASSERT_EQ(g.height, 5);
  EXPECT_EQ(at(g, 0, 1), (Vec3{240, 112, 0}));
  EXPECT_EQ(at(g, 1, 2), (Vec3{192, 192, 128}));
}

TEST(Patch, ExplicitSubdivisionsSampleTheBezier) {
  MapPatch p = quarterCylinder(256);
  p.explicitSubdivisions = true;
  p.horzSubdivisions = 4;
  p.vertSubdivisions = 3;
  const PatchGrid g = subdividePatchForCollision(p);
  ASSERT_EQ(g.width, 5);
  ASSERT_EQ(g.height, 2);  // 4 rows sampled, the straight inner ones removed
  EXPECT_EQ(at(g, 0, 0), (Vec3{256, 0, 0}));
  EXPECT_EQ(at(g, 1, 0), (Vec3{240, 112, 0}));
  EXPECT_EQ(at(g, 2, 1), (Vec3{192, 192, 128}));
  EXPECT_EQ(at(g, 4, 1), (Vec3{0, 256, 128}));

  // A flat patchDef3 keeps only its corners.
  MapPatch flat = patchFromColumns({{{0, 0, 0}, {0, 32, 0}, {0, 64, 0}},
                                    {{32, 0, 0}, {32, 32, 0}, {32, 64, 0}},
                                    {{64, 0, 0}, {64, 32, 0}, {64, 64, 0}}});
  flat.explicitSubdivisions = true;
  flat.horzSubdivisions = 6;
  flat.vertSubdivisions = 1;
  const PatchGrid fg = subdividePatchForCollision(flat);
  EXPECT_EQ(fg.width, 2);
  EXPECT_EQ(fg.height, 2);
}

TEST(Patch, ExplicitSubdivisionsOfSeveralBlocks) {
  // 5 x 3 control points: two blocks along the width, each sampled 3 times:
  // (5 - 1) / 2 * 3 + 1 = 7 columns, curved so none is removed.
  auto column = [](float x, float y) { return std::vector<Vec3>{{x, y, 0}, {x, y, 64}, {x, y, 128}}; };
  MapPatch p = patchFromColumns(
      {column(256, 0), column(256, 256), column(0, 256), column(-256, 256), column(-256, 0)});
  p.explicitSubdivisions = true;
  p.horzSubdivisions = 3;
  p.vertSubdivisions = 1;
  const PatchGrid g = subdividePatchForCollision(p);
  ASSERT_EQ(g.width, 7);
  ASSERT_EQ(g.height, 2);
  EXPECT_EQ(at(g, 3, 0), (Vec3{0, 256, 0}));  // the shared block border
  EXPECT_EQ(at(g, 6, 1), (Vec3{-256, 0, 128}));
}

TEST(Patch, BezierSampleUsesTheOriginalFormula) {
  CMKIT_FLOAT_BUILD_ONLY();
  const Vec3 ctrl[3][3] = {{{0, 0, 0}, {0, 10, 0}, {0, 20, 0}},
                           {{10, 0, 5}, {10, 10, 5}, {10, 20, 5}},
                           {{20, 0, 0}, {20, 10, 0}, {20, 20, 0}}};
  EXPECT_EQ(cmkit::detail::sampleBezierPatchPoint(ctrl, 0, 0), (Vec3{0, 0, 0}));
  EXPECT_EQ(cmkit::detail::sampleBezierPatchPoint(ctrl, 0.5f, 0.5f), (Vec3{10, 10, 2.5f}));
  EXPECT_EQ(cmkit::detail::sampleBezierPatchPoint(ctrl, 1, 1), (Vec3{20, 20, 0}));
  // q(1/3) with a=0, b=5, c=0: (0 - 10 + 0)/9 + 10/3, in float.
  const float u = 1.0f / 3.0f;
  const float qa = 0.0f - 2.0f * 5.0f + 0.0f;
  const float qb = 2.0f * 5.0f - 2.0f * 0.0f;
  EXPECT_EQ(cmkit::detail::sampleBezierPatchPoint(ctrl, u, 0).z, qa * u * u + qb * u + 0.0f);
}

TEST(Patch, InvalidPatchesGiveAnEmptyGrid) {
  MapPatch even;
  even.width = 2;
  even.height = 2;
  even.points.resize(4);
  EXPECT_TRUE(subdividePatchForCollision(even).points.empty());
  MapPatch mismatch = quarterCylinder(64);
  mismatch.points.pop_back();
  EXPECT_TRUE(subdividePatchForCollision(mismatch).points.empty());
  MapPatch huge = quarterCylinder(64);
  huge.explicitSubdivisions = true;
  huge.horzSubdivisions = 100000;
  huge.vertSubdivisions = 100000;
  EXPECT_TRUE(subdividePatchForCollision(huge).points.empty());
}

TEST(Patch, HugeCoordinatesDoNotRunAway) {
  const PatchGrid g = subdividePatchForCollision(quarterCylinder(1e30f));
  EXPECT_GT(g.width, 3);
  EXPECT_LE(static_cast<long long>(g.width) * g.height, cmkit::tol::kMaxPatchGridPoints);
  // NaN never compares greater: no split, and the middle column counts as
  // straight (as in the original), so it is removed.
  MapPatch nan = quarterCylinder(std::nanf(""));
  EXPECT_EQ(subdividePatchForCollision(nan).width, 2);
}

// ---- Against the reference .cm files ----------------------------------------

std::string formatCm(float f) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10f", static_cast<double>(f));
  std::string s = buf;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

/// The original's vertex snapping: within 0.01 of an integer -> the integer.
float snap(float v) {
  const float r = std::floor(v + 0.5f);
  return std::fabs(v - r) < cmkit::tol::kIntegralEpsilon ? r : v;
}

TEST(PatchReference, EveryGridPointIsAVertexOfTheReferenceModel) {
  // Maps whose patches are neither chopped by brushes nor welded to other
  // vertices: every tessellated point must be printed exactly in the .cm.
  const std::pair<const char*, const char*> maps[] = {
      {"synthetic/inline_patch.map", "inline_patch.cm"},
      {"darkradiant-edgecases/modelexport_patch.map", "modelexport_patch.cm"},
      {"darkradiant-edgecases/weld_patches_out_of_bounds.map", "weld_patches_out_of_bounds.cm"}};
  int checked = 0;
  for (const auto& [mapName, cmName] : maps) {
    SCOPED_TRACE(mapName);
    const auto mapPath = cmkit::test::dataFile(std::string("maps/") + mapName);
    if (!std::filesystem::exists(mapPath)) {
      std::printf("note: %s left out: %s\n", mapName, cmkit::test::whyNotBundled(mapName).c_str());
      continue;
    }
    ++checked;
    auto map = cmkit::loadMapFile(mapPath.string());
    ASSERT_TRUE(map.ok()) << map.error().toString();
    std::set<std::string> vertices;
    std::istringstream cm(cmkit::test::readFile(cmkit::test::dataFile(std::string("reference/") + cmName)));
    for (std::string line; std::getline(cm, line);) {
      // Vertex lines read "/* N */ ( x y z )"; keep the three numbers as printed.
      const auto open = line.find("*/ (");
      if (line.find("/*") == std::string::npos || open == std::string::npos) continue;
      std::istringstream fields(line.substr(open + 4));
      std::string x, y, z, close;
      if (fields >> x >> y >> z >> close && close == ")") vertices.insert(x + " " + y + " " + z);
    }
    int points = 0;
    for (const auto& entity : map->entities) {
      for (const auto& prim : entity.primitives) {
        const auto* patch = std::get_if<MapPatch>(&prim);
        if (!patch) continue;
        const PatchGrid g = subdividePatchForCollision(*patch);
        for (const Vec3& p : g.points) {
          const std::string key = formatCm(snap(p.x)) + " " + formatCm(snap(p.y)) + " " + formatCm(snap(p.z));
          EXPECT_TRUE(vertices.count(key)) << "patch on line " << patch->line << ": (" << key << ")";
          ++points;
        }
      }
    }
    EXPECT_GT(points, 30);
  }
  EXPECT_GE(checked, 1);
}

}  // namespace
