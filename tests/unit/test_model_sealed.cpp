// The sealed CollisionModel (include/cmkit/model.h): made only from checked
// arrays, read through spans, its query data made with it and shared by its
// copies.
#include <gtest/gtest.h>

#include "cmkit/model.h"
#include "cmkit/validate.h"
#include "model/model_access.h"
#include "model/query_data.h"
#include "model_fixtures.h"

namespace cmkit {
namespace {

ModelArrays twoBoxes() {
  return test::ModelMaker()
      .addBox({{0, 0, 0}, {10, 10, 10}})
      .addBox({{20, 0, 0}, {30, 10, 10}})
      .buildArrays();
}

TEST(SealedModel, CreateTakesTheArraysAsGiven) {
  const ModelArrays arrays = twoBoxes();
  Result<ModelPtr> m = CollisionModel::create(arrays);
  ASSERT_TRUE(m.ok()) << m.error().toString();
  const CollisionModel& model = **m;
  EXPECT_EQ(model.name(), "test");
  EXPECT_EQ(model.vertices().size(), 16u);  // 8 per box
  EXPECT_EQ(model.numEdges(), 24u);         // 12 per box
  EXPECT_EQ(model.polygons().size(), 12u);  // 6 per box
  EXPECT_EQ(model.brushes().size(), 2u);
  EXPECT_EQ(model.bounds(), Bounds({0, 0, 0}, {30, 10, 10}));
  EXPECT_EQ(model.vertices().data(), model.arrays().vertices.data());  // spans of its own arrays
  EXPECT_EQ(model.arrays().polygonEdges, arrays.polygonEdges);
  ASSERT_NE(detail::queryDataOf(model), nullptr);
  // An edge use for every polygon edge entry.
  EXPECT_EQ(detail::queryDataOf(model)->edgeUses.size(), arrays.polygonEdges.size());
}

TEST(SealedModel, CopiesShareTheQueryData) {
  const ModelPtr m = *CollisionModel::create(twoBoxes());
  const CollisionModel copy = *m;
  EXPECT_EQ(detail::queryDataOf(copy), detail::queryDataOf(*m));
  EXPECT_EQ(copy.vertices().size(), m->vertices().size());
  EXPECT_NE(copy.vertices().data(), m->vertices().data());  // arrays copied, data shared
}

TEST(SealedModel, CreateRefusesArraysWithNumbersOutOfRange) {
  struct Case {
    const char* what;
    void (*breakIt)(ModelArrays&);
    const char* message;  // a piece of the error's text
  };
  const Case cases[] = {
      {"edge vertex", [](ModelArrays& a) { a.edges[1].vertex[1] = 99; }, "edge 1"},
      {"polygon edge", [](ModelArrays& a) { a.polygonEdges[2] = 1000; }, "polygon 0"},
      {"polygon reference", [](ModelArrays& a) { a.polygonRefs[0] = 12; }, "node 0"},
      {"brush planes", [](ModelArrays& a) { a.brushes[1].numPlanes = 100; }, "brush 1"},
      {"no root", [](ModelArrays& a) { a.nodes.clear(); }, "no tree but items"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    ModelArrays arrays = twoBoxes();
    c.breakIt(arrays);
    const Result<ModelPtr> m = CollisionModel::create(arrays);
    ASSERT_FALSE(m.ok());
    EXPECT_NE(m.error().message.find("not a valid collision model"), std::string::npos) << m.error().message;
    EXPECT_NE(m.error().message.find(c.message), std::string::npos) << m.error().message;
    EXPECT_FALSE(structureViolations(arrays).empty());
  }
}

TEST(SealedModel, OddGeometryIsAllowed) {
  // A polygon whose plane lies 5 units off its vertices: a violation of
  // geometry (queries handle it), not of structure.
  ModelArrays arrays = twoBoxes();
  arrays.polygons[0].plane.dist += 5;
  EXPECT_TRUE(structureViolations(arrays).empty());
  bool geometry = false;
  for (const Violation& v : validateModel(arrays)) geometry |= v.kind == Violation::Kind::Geometry;
  EXPECT_TRUE(geometry);
  EXPECT_TRUE(CollisionModel::create(arrays).ok());
}

}  // namespace
}  // namespace cmkit
