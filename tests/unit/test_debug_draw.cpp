// Debug drawing through a recording DebugDraw: what drawModel and drawTrace
// emit for hand-built models, and reading traces back from query/result lines.
#include <gtest/gtest.h>

#include <map>

#include "cmkit/tools/debug_draw.h"
#include "model_fixtures.h"

namespace cmkit {
namespace {

/// Counts primitives per kind and remembers their tags.
class Recorder final : public DebugDraw {
 public:
  void line(const Vec3& a, const Vec3& b, const Rgba&, const DrawTag& tag) override {
    ++lines[tag.kind];
    ends.push_back(a);
    ends.push_back(b);
  }
  void polygon(std::span<const Vec3> points, const Vec3&, const Rgba& color, const DrawTag& tag) override {
    ++polygons[tag.kind];
    vertices += points.size();
    contents.push_back(tag.contents);
    colors.push_back(color);
  }
  void text(const Vec3&, std::string_view, const Rgba&, const DrawTag& tag) override { ++texts[tag.kind]; }

  int lineCount(DrawKind k) const { return lines.count(k) ? lines.at(k) : 0; }
  int polygonCount() const { return polygons.count(DrawKind::Polygon) ? polygons.at(DrawKind::Polygon) : 0; }

  std::map<DrawKind, int> lines, polygons, texts;
  std::size_t vertices = 0;
  std::vector<std::uint32_t> contents;
  std::vector<Rgba> colors;
  std::vector<Vec3> ends;
};

constexpr Bounds kBox{{-16, -16, -16}, {16, 16, 16}};

CollisionModel oneBox() { return test::ModelMaker().addBox(kBox).build(); }

TEST(DebugDraw, FilledBoxDrawsSixQuads) {
  Recorder r;
  DrawOptions o;
  o.filled = true;
  drawModel(r, oneBox(), Placement{}, o);
  EXPECT_EQ(r.polygonCount(), 6);
  EXPECT_EQ(r.vertices, 24u);
  EXPECT_TRUE(r.lines.empty());
  for (const Rgba& c : r.colors) EXPECT_EQ(c, contentColor(contents::kSolid));
}

TEST(DebugDraw, WireBoxDrawsEachEdgeOnce) {
  Recorder r;
  drawModel(r, oneBox(), Placement{}, DrawOptions{});
  EXPECT_EQ(r.lineCount(DrawKind::Edge), 12);
  EXPECT_EQ(r.polygonCount(), 0);
}

TEST(DebugDraw, BackFaceCullingKeepsOnlyFacesTheViewerSees) {
  DrawOptions o;
  o.filled = true;
  o.backFaceCull = true;
  o.viewOrigin = {100, 0, 0};  // in front of +x only
  Recorder r;
  drawModel(r, oneBox(), Placement{}, o);
  EXPECT_EQ(r.polygonCount(), 1);
  o.viewOrigin = {100, 100, 100};  // a corner: three faces
  Recorder corner;
  drawModel(corner, oneBox(), Placement{}, o);
  EXPECT_EQ(corner.polygonCount(), 3);
  o.backFaceCull = false;
  Recorder all;
  drawModel(all, oneBox(), Placement{}, o);
  EXPECT_EQ(all.polygonCount(), 6);
}

TEST(DebugDraw, BackFaceCullingUsesThePlacedModel) {
  // The model moved far along +x: a viewer at x = 100 is now behind it.
  DrawOptions o;
  o.filled = true;
  o.backFaceCull = true;
  o.viewOrigin = {100, 0, 0};
  Placement p;
  p.origin = {1000, 0, 0};
  Recorder r;
  drawModel(r, oneBox(), p, o);
  EXPECT_EQ(r.polygonCount(), 1);
  for (const Vec3& v : r.ends) EXPECT_GT(v.x, 900);
}

TEST(DebugDraw, InternalEdgesOnlyOnRequest) {
  CollisionModel m = test::ModelMaker().addBox(kBox).markInternal(1).markInternal(5).build();
  Recorder without;
  drawModel(without, m, Placement{}, DrawOptions{});
  EXPECT_EQ(without.lineCount(DrawKind::Edge), 10);
  EXPECT_EQ(without.lineCount(DrawKind::InternalEdge), 0);
  DrawOptions o;
  o.internalEdges = true;
  Recorder with;
  drawModel(with, m, Placement{}, o);
  EXPECT_EQ(with.lineCount(DrawKind::Edge), 10);
  EXPECT_EQ(with.lineCount(DrawKind::InternalEdge), 2);
}

TEST(DebugDraw, ContentMaskSelectsPolygons) {
  CollisionModel m = test::ModelMaker()
                         .addBox(kBox, contents::kSolid)
                         .addBox({{100, -16, -16}, {132, 16, 16}}, contents::kWater)
                         .build();
  DrawOptions o;
  o.filled = true;
  Recorder all;
  drawModel(all, m, Placement{}, o);
  EXPECT_EQ(all.polygonCount(), 12);
  o.contentMask = contents::kWater;
  Recorder water;
  drawModel(water, m, Placement{}, o);
  EXPECT_EQ(water.polygonCount(), 6);
  for (std::uint32_t c : water.contents) EXPECT_EQ(c, contents::kWater);
  o.contentMask = contents::kPlayerClip;
  Recorder none;
  drawModel(none, m, Placement{}, o);
  EXPECT_EQ(none.polygonCount(), 0);
}

TEST(DebugDraw, RadiusKeepsPolygonsNearTheViewer) {
  CollisionModel m = test::ModelMaker().addBox(kBox).addBox({{1000, -16, -16}, {1032, 16, 16}}).build();
  DrawOptions o;
  o.filled = true;
  o.viewOrigin = {0, 0, 0};
  o.radius = 64;
  Recorder r;
  drawModel(r, m, Placement{}, o);
  EXPECT_EQ(r.polygonCount(), 6);
}

TEST(DebugDraw, NormalsForPolygonsAndEdges) {
  DrawOptions o;
  o.normals = true;
  o.filled = true;
  Recorder filled;
  drawModel(filled, oneBox(), Placement{}, o);
  EXPECT_EQ(filled.lineCount(DrawKind::PolygonNormal), 6);
  o.filled = false;
  Recorder wire;
  drawModel(wire, oneBox(), Placement{}, o);
  EXPECT_EQ(wire.lineCount(DrawKind::EdgeNormal), 12);
}

TEST(DebugDraw, FixedColourWhenNotByContents) {
  DrawOptions o;
  o.filled = true;
  o.colorByContents = false;
  o.color = colors::kCyan;
  Recorder r;
  drawModel(r, oneBox(), Placement{}, o);
  for (const Rgba& c : r.colors) EXPECT_EQ(c, colors::kCyan);
}

TEST(DebugDraw, TraceWithContact) {
  auto box = TraceModel::box({{-8, -8, -8}, {8, 8, 8}});
  ASSERT_TRUE(box);
  TraceDrawing t;
  t.trm = &*box;
  t.start = {0, 0, 100};
  t.end = {0, 0, -100};
  t.result.fraction = 0.4f;
  t.result.endPos = {0, 0, 20};
  t.result.contact.type = ContactType::TrmVertex;
  t.result.contact.point = {0, 0, 16};
  t.result.contact.normal = {0, 0, 1};
  Recorder r;
  drawTrace(r, t);
  EXPECT_EQ(r.lineCount(DrawKind::TracePath), 2);    // start->stop, stop->end
  EXPECT_EQ(r.lineCount(DrawKind::TraceModel), 24);  // the box at start and at the end pose
  EXPECT_EQ(r.lineCount(DrawKind::Contact), 3);      // a cross
  EXPECT_EQ(r.lineCount(DrawKind::ContactNormal), 1);
}

TEST(DebugDraw, TraceWithoutContactHasNoMarker) {
  TraceDrawing t;
  t.start = {0, 0, 0};
  t.end = {10, 0, 0};
  t.result.endPos = t.end;
  Recorder r;
  drawTrace(r, t);
  EXPECT_EQ(r.lineCount(DrawKind::TracePath), 1);
  EXPECT_EQ(r.lineCount(DrawKind::Contact), 0);
  EXPECT_EQ(r.lineCount(DrawKind::TraceModel), 6);  // point crosses at start and end
}

TEST(DebugDraw, ContentStyleTableCoversEveryNamedFlag) {
  ASSERT_EQ(contentStyles().size(), contentNames().size());
  for (std::size_t i = 0; i < contentNames().size(); ++i) {
    EXPECT_EQ(contentStyles()[i].name, contentNames()[i].name);
    EXPECT_EQ(contentStyles()[i].flag, contentNames()[i].flag);
  }
  EXPECT_EQ(contentColor(contents::kWater | contents::kPlayerClip), contentColor(contents::kWater));
  EXPECT_NE(contentColor(contents::kWater), contentColor(contents::kSolid));
}

constexpr const char* kQueries =
    "# two traces\n"
    "translation trm=box:-8,-8,-8,8,8,8 start=0,0,100 end=0,0,-100\n"
    "\n"
    "pointcontents pos=1,2,3\n"
    "contacts trm=point start=0,0,8 dir=0,0,-1 depth=16\n";
constexpr const char* kResults =
    "fraction=0.5 endpos=0,0,0 endaxis=1,0,0,0,1,0,0,0,1 type=trmvertex point=1,2,3 normal=0,0,1 dist=3 "
    "contents=1 material=- modelfeature=4 trmfeature=7\n"
    "contents=1\n"
    "count=1 type.0=edge point.0=0,0,0 normal.0=0,0,1 dist.0=0 contents.0=1 material.0=- modelfeature.0=-3 "
    "trmfeature.0=2\n";

TEST(DebugDraw, TraceRecordsFromQueryAndResultFiles) {
  const auto records = parseTraceRecords(kQueries, kResults);
  ASSERT_EQ(records.size(), 3u);
  const TraceRecord& t = records[0];
  EXPECT_EQ(t.op, "translation");
  EXPECT_TRUE(t.error.empty()) << t.error;
  ASSERT_TRUE(t.trm.has_value());
  EXPECT_EQ(t.trm->shape(), TrmShape::Box);
  EXPECT_EQ(t.end, (Vec3{0, 0, -100}));
  EXPECT_EQ(t.result.fraction, 0.5f);
  EXPECT_EQ(t.result.contact.type, ContactType::TrmVertex);
  EXPECT_EQ(t.result.contact.point, (Vec3{1, 2, 3}));
  EXPECT_EQ(t.result.contact.modelFeature, 4);
  EXPECT_EQ(t.result.contact.trmFeature, 7);
  EXPECT_EQ(records[1].op, "pointcontents");
  EXPECT_EQ(records[2].result.contact.type, ContactType::Edge);
  EXPECT_EQ(records[2].result.contact.modelFeature, -3);
  EXPECT_EQ(records[2].end, (Vec3{0, 0, -8}));
}

TEST(DebugDraw, TraceRecordsFromOneInterleavedFile) {
  const std::string both =
      "translation trm=point start=0,0,10 end=0,0,-10\n"
      "fraction=1 endpos=0,0,-10 endaxis=1,0,0,0,1,0,0,0,1 type=none point=0,0,0 normal=0,0,0 dist=0 "
      "contents=0 material=- modelfeature=0 trmfeature=0\n"
      "translation trm=box:1,1,1,0,0,0 start=0,0,0 end=1,1,1\n"
      "error=degenerate trm (max below min)\n";
  const auto records = parseTraceRecords("", both);
  ASSERT_EQ(records.size(), 2u);
  EXPECT_TRUE(records[0].error.empty());
  EXPECT_EQ(records[0].result.endPos, (Vec3{0, 0, -10}));
  EXPECT_FALSE(records[1].error.empty());
  Recorder r;
  drawTraceRecords(r, records);  // the error line is skipped
  EXPECT_EQ(r.lineCount(DrawKind::TracePath), 1);
}

TEST(DebugDraw, MalformedTraceLinesGiveErrorsNotCrashes) {
  const auto records = parseTraceRecords("translation start=1,2\nbogus\n", "fraction=x\n");
  ASSERT_EQ(records.size(), 2u);
  EXPECT_FALSE(records[0].error.empty());
  EXPECT_EQ(records[1].error, "no result line");
}

}  // namespace
}  // namespace cmkit
