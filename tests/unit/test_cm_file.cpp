// .cm reading and writing: the project's own files, hand-written models,
// the original's number format, tree filtering order and error messages.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "cm_test_util.h"
#include "cmkit/cm_file.h"
#include "cmkit/contents.h"
#include "cmkit/validate.h"
#include "model/edge_normals.h"
#include "test_support.h"

namespace cmkit {
namespace {

using test::modelDifference;

// The hand-written model of docs/cm-format.md: a 128x128 floor on a slab.
constexpr std::string_view kFloorCm = R"(CM "1.00"

0

collisionModel "worldMap" {
	vertices { /* numVertices = */ 4
	/* 0 */ ( -64 -64 0 )
	/* 1 */ ( 64 -64 0 )
	/* 2 */ ( 64 64 0 )
	/* 3 */ ( -64 64 0 )
	}
	edges { /* numEdges = */ 5
	/* 0 */ ( 0 0 ) 0 0
	/* 1 */ ( 0 1 ) 0 1
	/* 2 */ ( 1 2 ) 0 1
	/* 3 */ ( 2 3 ) 0 1
	/* 4 */ ( 3 0 ) 0 1
	}
	nodes {
	( -1 0 )
	}
	polygons /* polygonMemory = */ 76 {
	4 ( 1 2 3 4 ) ( 0 0 1 ) 0 ( -64 -64 0 ) ( 64 64 0 ) "textures/example/floor"
	}
	brushes /* brushMemory = */ 144 {
	6 {
		( 0 0 1 ) 0
		( 0 0 -1 ) 16
		( 1 0 0 ) 64
		( -1 0 0 ) 64
		( 0 1 0 ) 64
		( 0 -1 0 ) 64
	} ( -64 -64 -16 ) ( 64 64 0 ) "solid,opaque"
	}
}
)";

CmFile mustParse(std::string_view text, const std::string& name = "test.cm") {
  Result<CmFile> r = parseCmText(text, name, MaterialTable{});
  EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().toString());
  return r.ok() ? std::move(r.value()) : CmFile{};
}

Error mustFail(std::string_view text) {
  Result<CmFile> r = parseCmText(text, "bad.cm", MaterialTable{});
  EXPECT_FALSE(r.ok()) << "parsed although malformed:\n" << text;
  return r.ok() ? Error{} : r.error();
}

std::string replaced(std::string_view text, std::string_view from, std::string_view to) {
  std::string s(text);
  const std::size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(CmFile, SpecExampleLoadsWithRecomputedData) {
  const CmFile f = mustParse(kFloorCm);
  ASSERT_EQ(f.models.size(), 1u);
  const CollisionModel& m = *f.models[0];
  EXPECT_EQ(f.crc, 0u);
  EXPECT_EQ(m.name(), "worldMap");
  EXPECT_EQ(m.vertices().size(), 4u);
  EXPECT_EQ(m.numEdges(), 4u);
  ASSERT_EQ(m.polygons().size(), 1u);
  ASSERT_EQ(m.brushes().size(), 1u);
  // Polygon contents from the material (default rules: solid, opaque);
  // brushes get no material.
  EXPECT_EQ(m.polygons()[0].contents, contents::kSolid | contents::kOpaque);
  EXPECT_EQ(m.materialName(m.polygons()[0].material), "textures/example/floor");
  EXPECT_EQ(m.brushes()[0].material, -1);
  EXPECT_EQ(m.brushes()[0].contents, contents::kSolid | contents::kOpaque);
  EXPECT_EQ(m.contents(), contents::kSolid | contents::kOpaque);
  EXPECT_EQ(m.bounds(), Bounds(Vec3(-64, -64, -16), Vec3(64, 64, 0)));
  // Boundary edges get their outward in-plane normal: edge 1 runs along y = -64.
  EXPECT_EQ(m.edges()[1].normal, Vec3(0, -1, 0));
  EXPECT_EQ(m.edges()[2].normal, Vec3(1, 0, 0));
  EXPECT_EQ(m.nodes().size(), 1u);
  EXPECT_EQ(test::toVector(m.polygonRefs()), std::vector<std::int32_t>{0});
  EXPECT_EQ(test::toVector(m.brushRefs()), std::vector<std::int32_t>{0});
  EXPECT_TRUE(validateModel(m).empty());
  EXPECT_EQ(writeCmText(f.models, f.crc), kFloorCm);
}

TEST(CmFile, SectionsInAnyOrderCommentsIntegerContentsNoHints) {
  const std::string text = R"(// a comment
CM "1.00" /* another */ 12345
collisionModel "m" {
  brushes { 1 { ( 0 0 1 ) 5 } ( 0 0 0 ) ( 1 1 5 ) 9 }
  polygons { 3 ( 1 2 3 ) ( 0 0 1 ) 0 ( 0 0 0 ) ( 1 1 0 ) "Textures\Base\Floor.tga" }
  edges { 4 ( 0 0 ) 0 0 ( 0 1 ) 0 1 ( 1 2 ) 0 1 ( 2 0 ) 0 1 }
  vertices { 3 ( 0 0 0 ) ( 1 0 0 ) ( 0 1 0 ) }
  nodes { ( -1 0 ) }
}
collisionModel "m" { }
)";
  const CmFile f = mustParse(text);
  EXPECT_EQ(f.crc, 12345u);
  ASSERT_EQ(f.models.size(), 2u);
  const CollisionModel& m = *f.models[0];
  EXPECT_EQ(m.brushes()[0].contents, contents::kSolid | contents::kPlayerClip);  // the integer 9
  EXPECT_EQ(m.materialName(m.polygons()[0].material), "textures/base/floor");  // canonical, as the decl name
  // A model with no sections at all: one empty leaf, zero bounds.
  const CollisionModel& empty = *f.models[1];
  EXPECT_EQ(empty.name(), "m");
  EXPECT_EQ(empty.nodes().size(), 1u);
  EXPECT_EQ(empty.bounds(), Bounds(Vec3{}, Vec3{}));
}

// Items are filtered into the stored tree by their bounds and prepended to
// each node's list (docs/cm-format.md).
TEST(CmFile, ItemsAreFilteredIntoTheTreeAndPrepended) {
  // Root splits x at 0; its front child splits y at 0.
  const std::string text = R"(CM "1.00" 0
collisionModel "t" {
  vertices { 3 ( 0 0 0 ) ( 1 0 0 ) ( 0 1 0 ) }
  edges { 4 ( 0 0 ) 0 0 ( 0 1 ) 0 1 ( 1 2 ) 0 1 ( 2 0 ) 0 1 }
  nodes { ( 0 0 ) ( 1 0 ) ( -1 0 ) ( -1 0 ) ( -1 0 ) }
  polygons {
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( 1 1 0 ) ( 2 2 0 ) "a"
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( -2 -2 0 ) ( -1 -1 0 ) "a"
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( 1 -1 0 ) ( 2 1 0 ) "a"
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( -1 -1 0 ) ( 1 1 0 ) "a"
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( 3 3 0 ) ( 4 4 0 ) "a"
    3 ( 1 2 3 ) ( 0 0 1 ) 0 ( -1 2 0 ) ( 1 3 0 ) "a"
  }
}
)";
  const CmFile f = mustParse(text);
  const CollisionModel& m = *f.models[0];
  ASSERT_EQ(m.nodes().size(), 5u);
  EXPECT_EQ(m.nodes()[0].children[0], 1);
  EXPECT_EQ(m.nodes()[0].children[1], 4);
  EXPECT_EQ(m.nodes()[1].children[0], 2);
  EXPECT_EQ(m.nodes()[1].children[1], 3);
  EXPECT_EQ(m.nodes()[3].parent, 1);
  auto at = [&](int n) {
    const auto s = m.polygonsAt(m.nodes()[std::size_t(n)]);
    return std::vector<std::int32_t>(s.begin(), s.end());
  };
  // Polygon 3 straddles both planes: it stays at the root. Polygon 5
  // straddles x = 0 only: front (y) and back leaves. Polygon 2 straddles
  // y = 0 below the root: it stops at node 1, inside all its children.
  EXPECT_EQ(at(0), (std::vector<std::int32_t>{3}));
  EXPECT_EQ(at(1), (std::vector<std::int32_t>{2}));
  EXPECT_EQ(at(2), (std::vector<std::int32_t>{5, 4, 0}));  // reverse file order
  EXPECT_EQ(at(3), (std::vector<std::int32_t>{}));
  EXPECT_EQ(at(4), (std::vector<std::int32_t>{5, 1}));
  // Without memory hints the sections open plainly.
  const std::string plain = writeCmText(f.models, 0, {.memoryHints = false});
  EXPECT_NE(plain.find("\tpolygons {\n"), std::string::npos);
  EXPECT_NE(plain.find("\tbrushes {\n"), std::string::npos);
}

TEST(CmFile, NumbersAreWrittenAsTheOriginalPrintsThem) {
  EXPECT_EQ(formatCmFloat(0.5f), "0.5");
  EXPECT_EQ(formatCmFloat(64.0f), "64");
  EXPECT_EQ(formatCmFloat(-0.0f), "-0");
  EXPECT_EQ(formatCmFloat(0.0f), "0");
  EXPECT_EQ(formatCmFloat(-1e-12f), "-0");
  EXPECT_EQ(formatCmFloat(1e-12f), "0");
  EXPECT_EQ(formatCmFloat(352.0000305176f), "352.0000305176");
  EXPECT_EQ(formatCmFloat(1952.0078125f), "1952.0078125");
  EXPECT_EQ(formatCmFloat(0.0001234f), "0.0001234");
  EXPECT_EQ(formatCmFloat(123456789.0f), "123456792");
  EXPECT_EQ(formatCmFloat(1e30f), "1000000015047466219876688855040");
  EXPECT_EQ(formatCmFloat(-1e30f), "-1000000015047466219876688855040");
  EXPECT_EQ(formatCmFloat(std::numeric_limits<float>::max()), "340282346638528859811704183484516925440");
}

TEST(CmFile, NegativeZeroAndLargeValuesSurviveTheRoundTrip) {
  const std::string text = replaced(replaced(kFloorCm, "( 0 0 1 ) 0 ( -64", "( 0 -0 1 ) -0 ( -64"),
                                    "( 64 64 0 ) \"t", "( 1000000015047466219876688855040 64 0 ) \"t");
  const CmFile f = mustParse(text);
  EXPECT_TRUE(std::signbit(f.models[0]->polygons()[0].plane.dist));
  EXPECT_EQ(f.models[0]->polygons()[0].bounds.max.x, 1e30f);
  EXPECT_EQ(writeCmText(f.models, f.crc), text);
}

TEST(CmFile, ErrorsNameFileLineAndColumn) {
  Error e = mustFail(replaced(kFloorCm, "( 3 0 ) 0 1", "( 3 9 ) 0 1"));
  EXPECT_EQ(e.file, "bad.cm");
  EXPECT_EQ(e.line, 17);
  EXPECT_EQ(e.column, 10);
  EXPECT_NE(e.message.find("vertex 9"), std::string::npos) << e.message;

  e = mustFail(replaced(kFloorCm, "4 ( 1 2 3 4 )", "2 ( 1 2 )"));
  EXPECT_NE(e.message.find("number of polygon edges"), std::string::npos) << e.message;
  e = mustFail(replaced(kFloorCm, "4 ( 1 2 3 4 )", "4 ( 1 2 3 5 )"));
  EXPECT_NE(e.message.find("uses edge 5"), std::string::npos) << e.message;
  e = mustFail(replaced(kFloorCm, "4 ( 1 2 3 4 )", "4 ( 1 2 3 0 )"));
  e = mustFail(replaced(kFloorCm, "\"solid,opaque\"", "\"solid,stone\""));
  EXPECT_NE(e.message.find("stone"), std::string::npos) << e.message;
  EXPECT_EQ(e.line, 33);
  e = mustFail(replaced(kFloorCm, "( 64 -64 0 )", "( 64 -64 1e39 )"));
  EXPECT_NE(e.message.find("finite"), std::string::npos) << e.message;
  e = mustFail(replaced(kFloorCm, "\"1.00\"", "\"2.00\""));
  EXPECT_NE(e.message.find("version"), std::string::npos) << e.message;
  e = mustFail(replaced(kFloorCm, "CM", "XM"));
  e = mustFail(replaced(kFloorCm, "nodes {", "nodes { ( 3 0 ) "));
  e = mustFail(replaced(kFloorCm, "\tnodes {", "\tvertices { 0 }\n\tnodes {"));
  EXPECT_NE(e.message.find("repeated"), std::string::npos) << e.message;
  e = mustFail(replaced(kFloorCm, "/* 1 */ ( 0 1 ) 0 1", "/* 1 */ ( 0 1.5 ) 0 1"));
  e = mustFail(replaced(kFloorCm, "vertices { /* numVertices = */ 4", "vertices { /* numVertices = */ 5"));
  e = mustFail(std::string(kFloorCm) + "/* unterminated");
  EXPECT_NE(e.message.find("comment"), std::string::npos) << e.message;
  e = mustFail(std::string(kFloorCm) + "garbage");
  e = mustFail(replaced(kFloorCm, "\"worldMap\"", "worldMap"));
  // Edges that do not outline the polygon (found by fuzzing): an error at the polygon.
  e = mustFail(replaced(kFloorCm, "4 ( 1 2 3 4 )", "4 ( 1 3 2 4 )"));
  EXPECT_NE(e.message.find("polygon 0: its edges do not form a loop"), std::string::npos) << e.message;
  EXPECT_EQ(e.line, 23);
}

TEST(CmFile, EdgeNormalsOfAFoldAndASharpEdge) {
  // Two triangles sharing edge 1 (0 -> 1 along x): one in z = 0 facing +z,
  // the other folded back onto it (facing -z, slightly tilted): sharp.
  ModelArrays m;
  m.vertices = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 10, 1}};
  m.edges.resize(6);
  m.edges[1] = CmEdge{{0, 1}, false, 2, {}};
  m.edges[2] = CmEdge{{1, 2}, false, 1, {}};
  m.edges[3] = CmEdge{{2, 0}, false, 1, {}};
  m.edges[4] = CmEdge{{1, 3}, false, 1, {}};
  m.edges[5] = CmEdge{{3, 0}, false, 1, {}};
  m.polygonEdges = {1, 2, 3, -1, -5, -4};
  CmPolygon a;
  a.plane = Plane({0, 0, 1}, 0);
  a.numEdges = 3;
  CmPolygon b;
  b.plane = Plane(Vec3(0, 1, -10).normalized(), 0);
  b.firstEdge = 3;
  b.numEdges = 3;
  m.polygons = {a, b};
  CmNode leaf;
  leaf.numPolygonRefs = 2;
  m.nodes = {leaf};
  m.polygonRefs = {0, 1};
  EXPECT_EQ(detail::computeEdgeNormals(m), 1);
  // The sharp edge's normal points out of both faces (-y) with length 1/0.3.
  const Vec3 n = m.edges[1].normal;
  EXPECT_LT(n.y, 0);
  EXPECT_NEAR(n.length(), 1 / 0.3, 1e-3);
  EXPECT_NEAR(n.x, 0, 1e-6);
  // Again: the pass resets and recomputes.
  EXPECT_EQ(detail::computeEdgeNormals(m), 1);
  EXPECT_EQ(m.edges[1].normal, n);
  // Boundary edge 2 of polygon a: outward in-plane normal.
  EXPECT_NEAR(m.edges[2].normal.x, std::sqrt(0.5), 1e-6);
  EXPECT_NEAR(m.edges[2].normal.y, std::sqrt(0.5), 1e-6);
}

// Every .cm of the project's own data: loads, validates, and is written back
// byte for byte; reading that again gives the same model.
TEST(CmFile, ProjectFilesRoundTrip) {
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(test::testDataDir() / "cm")) {
    if (entry.path().extension() != ".cm") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    const std::string text = test::readFile(entry.path());
    const CmFile f = mustParse(text, entry.path().string());
    ASSERT_FALSE(f.models.empty());
    for (const ModelPtr& m : f.models) {
      for (const Violation& v : validateModel(*m)) ADD_FAILURE() << v.toString();
    }
    const std::string written = writeCmText(f.models, f.crc);
    EXPECT_EQ(written, text);
    const CmFile again = mustParse(written);
    ASSERT_EQ(again.models.size(), f.models.size());
    for (std::size_t i = 0; i < f.models.size(); ++i)
      EXPECT_EQ(modelDifference(*f.models[i], *again.models[i]), "") << "model " << i;
  }
  EXPECT_EQ(files, 3);
}

TEST(CmFile, Ep1ModelZeroIsNotWorldMapAndNamesRepeat) {
  const CmFile f = mustParse(test::readFile(test::testDataDir() / "cm" / "ep1.cm"));
  ASSERT_EQ(f.models.size(), 4u);
  EXPECT_EQ(f.crc, 4280070210u);
  EXPECT_EQ(f.models[0]->name(), "func_static_2");
  int repeated = 0;
  for (std::size_t i = 0; i < f.models.size(); ++i)
    for (std::size_t j = i + 1; j < f.models.size(); ++j)
      repeated += f.models[i]->name() == f.models[j]->name();
  EXPECT_GT(repeated, 0);
}

TEST(CmFile, BlenderModelHasNoBrushes) {
  const CmFile f = mustParse(test::readFile(test::testDataDir() / "cm" / "blender_misc_model1.cm"));
  ASSERT_FALSE(f.models.empty());
  for (const ModelPtr& m : f.models) {
    EXPECT_TRUE(m->brushes().empty());
    EXPECT_FALSE(m->polygons().empty());
  }
}

TEST(CmFile, LoadAndSaveFiles) {
  const test::ScratchDir scratch("cm_file");
  const std::filesystem::path& dir = scratch.path();
  const CmFile f = mustParse(kFloorCm);
  ASSERT_TRUE(saveCmFile((dir / "floor.cm").string(), f.models, 77).ok());
  Result<CmFile> loaded = loadCmFile((dir / "floor.cm").string(), MaterialTable{});
  ASSERT_TRUE(loaded.ok());
  EXPECT_EQ(loaded->crc, 77u);
  EXPECT_EQ(modelDifference(*loaded->models[0], *f.models[0]), "");
  Result<std::uint32_t> crc = readCmFileCrc((dir / "floor.cm").string());
  ASSERT_TRUE(crc.ok());
  EXPECT_EQ(*crc, 77u);
  EXPECT_FALSE(loadCmFile((dir / "missing.cm").string(), MaterialTable{}).ok());
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cmkit
