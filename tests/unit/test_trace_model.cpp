// Trace model shapes: feature counts, topology, planes, convexity, bounds,
// the original's numbering, mass properties, transformations and every
// rejection.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <numbers>
#include <random>
#include <vector>

#include "cmkit/trace_model.h"

using namespace cmkit;

namespace {

// Independent checks of a closed convex solid (not using checkInvariants).
void expectClosedConvexSolid(const TraceModel& t) {
  SCOPED_TRACE(std::string(toString(t.shape())));
  ASSERT_TRUE(t.isConvex());
  EXPECT_EQ(t.numVertices() - t.numEdges() + t.numPolygons(), 2);  // Euler
  Vec3 centre;
  for (const Vec3& v : t.vertices()) centre += v;
  centre = centre * (1.0f / float(t.numVertices()));
  const Real scale = std::max(Real(1), (t.bounds().max - t.bounds().min).length());
  std::vector<int> uses(size_t(t.numEdges() + 1), 0);
  for (const TrmPolygon& p : t.polygons()) {
    EXPECT_NEAR(p.normal.length(), 1.0f, 1e-5f);
    EXPECT_LT(p.normal.dot(centre) - p.dist, 0.0f) << "normal must point away from the centre";
    Vec3 areaNormal;  // Newell: direction of the loop's winding
    for (int j = 0; j < p.numEdges; ++j) {
      const int e = p.edges[size_t(j)];
      ASSERT_NE(e, 0);
      uses[size_t(std::abs(e))] += e > 0 ? 1 : 100;
      const TrmEdge& edge = t.edge(std::abs(e));
      const int from = e > 0 ? edge.v[0] : edge.v[1];
      const int to = e > 0 ? edge.v[1] : edge.v[0];
      const int nextFrom = p.startVertex(t, (j + 1) % p.numEdges);
      EXPECT_EQ(to, nextFrom) << "edge loop must be continuous";
      EXPECT_NEAR(p.normal.dot(t.vertex(from)), p.dist, 1e-4f * scale) << "vertex on its plane";
      areaNormal += t.vertex(from).cross(t.vertex(to));
      EXPECT_TRUE(p.bounds.expanded(1e-4f * scale).containsPoint(t.vertex(from)));
    }
    EXPECT_GT(areaNormal.dot(p.normal), 0.0f) << "edges counter-clockwise around the normal";
    for (const Vec3& v : t.vertices()) EXPECT_LE(p.normal.dot(v) - p.dist, 1e-4f * scale) << "convex";
  }
  for (int e = 1; e <= t.numEdges(); ++e)
    EXPECT_EQ(uses[size_t(e)], 101) << "edge " << e << " used once each way";
  Bounds b;
  for (const Vec3& v : t.vertices()) b.addPoint(v);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(b.min[k], t.bounds().min[k], 1e-4f * scale);
    EXPECT_NEAR(b.max[k], t.bounds().max[k], 1e-4f * scale);
  }
  EXPECT_EQ(t.checkInvariants(), "");
}

const Bounds kSizes[] = {
    {{-16, -16, 0}, {16, 16, 72}},
    {{-1, -2, -3}, {1, 2, 3}},
    {{100, 200, -50}, {164, 232, 30}},
    {{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}},
};

}  // namespace

TEST(TraceModel, BoxFeaturesAndNumbering) {
  for (const Bounds& b : kSizes) {
    auto t = TraceModel::box(b);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->shape(), TrmShape::Box);
    EXPECT_EQ(t->numVertices(), 8);
    EXPECT_EQ(t->numEdges(), 12);
    EXPECT_EQ(t->numPolygons(), 6);
    expectClosedConvexSolid(*t);
    EXPECT_EQ(t->bounds(), b);
    EXPECT_EQ(t->offset(), b.center());
    // original numbering: vertex 0 = min corner, 6 = max corner, 0..3 bottom CCW
    EXPECT_EQ(t->vertex(0), b.min);
    EXPECT_EQ(t->vertex(6), b.max);
    EXPECT_EQ(t->vertex(1), Vec3(b.max.x, b.min.y, b.min.z));
    EXPECT_EQ(t->vertex(3), Vec3(b.min.x, b.max.y, b.min.z));
    EXPECT_EQ(t->edge(1).v[0], 0);
    EXPECT_EQ(t->edge(1).v[1], 1);
    EXPECT_EQ(t->edge(9).v[0], 0);
    EXPECT_EQ(t->edge(9).v[1], 4);
    const Vec3 normals[6] = {{0, 0, -1}, {0, 0, 1}, {0, -1, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}};
    for (int i = 0; i < 6; ++i) EXPECT_EQ(t->polygon(i).normal, normals[i]);
    EXPECT_EQ(t->polygon(1).dist, b.max.z);
  }
}

TEST(TraceModel, Octahedron) {
  for (const Bounds& b : kSizes) {
    auto t = TraceModel::octahedron(b);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->numVertices(), 6);
    EXPECT_EQ(t->numEdges(), 12);
    EXPECT_EQ(t->numPolygons(), 8);
    expectClosedConvexSolid(*t);
    EXPECT_EQ(t->vertex(0), Vec3(b.max.x, b.center().y, b.center().z));
    EXPECT_EQ(t->vertex(5), Vec3(b.center().x, b.center().y, b.min.z));
  }
}

TEST(TraceModel, Dodecahedron) {
  for (const Bounds& b : kSizes) {
    auto t = TraceModel::dodecahedron(b);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(t->numVertices(), 20);
    EXPECT_EQ(t->numEdges(), 30);
    EXPECT_EQ(t->numPolygons(), 12);
    expectClosedConvexSolid(*t);
    for (const TrmPolygon& p : t->polygons()) EXPECT_EQ(p.numEdges, 5);
  }
}

TEST(TraceModel, CylinderEverySideCount) {
  for (const Bounds& b : kSizes) {
    for (int n = 3; n <= 10; ++n) {
      auto t = TraceModel::cylinder(b, n);
      ASSERT_TRUE(t.ok()) << n;
      EXPECT_EQ(t->numVertices(), 2 * n);
      EXPECT_EQ(t->numEdges(), 3 * n);
      EXPECT_EQ(t->numPolygons(), n + 2);
      expectClosedConvexSolid(*t);
      // vertex 0 at angle 0 on the bottom
      EXPECT_NEAR(t->vertex(0).x, b.max.x, 1e-4f);
      EXPECT_NEAR(t->vertex(0).z, b.min.z, 1e-4f);
    }
  }
}

TEST(TraceModel, ConeEverySideCount) {
  for (const Bounds& b : kSizes) {
    for (int n = 3; n <= 15; ++n) {
      auto t = TraceModel::cone(b, n);
      ASSERT_TRUE(t.ok()) << n;
      EXPECT_EQ(t->numVertices(), n + 1);
      EXPECT_EQ(t->numEdges(), 2 * n);
      EXPECT_EQ(t->numPolygons(), n + 1);
      expectClosedConvexSolid(*t);
      EXPECT_EQ(t->vertex(n), Vec3(b.center().x, b.center().y, b.max.z));  // apex
    }
  }
}

TEST(TraceModel, Bone) {
  for (float len : {10.0f, 43.0f, 62.0f}) {
    for (float width : {2.0f, 6.0f, 27.0f}) {
      auto t = TraceModel::bone(len, width);
      ASSERT_TRUE(t.ok());
      EXPECT_EQ(t->numVertices(), 5);
      EXPECT_EQ(t->numEdges(), 9);
      EXPECT_EQ(t->numPolygons(), 6);
      expectClosedConvexSolid(*t);
      EXPECT_EQ(t->vertex(0), Vec3(0, 0, -len / 2));
      EXPECT_EQ(t->vertex(4), Vec3(0, 0, len / 2));
      // vertex 1 at (0, -w/2, 0), vertex 2 at (w/2, w/4, 0): as reported by the
      // original's query results (trmfeature of bone contacts).
      EXPECT_EQ(t->vertex(1), Vec3(0, -width / 2, 0));
      EXPECT_EQ(t->vertex(2), Vec3(width / 2, width / 4, 0));
      EXPECT_EQ(t->offset(), Vec3(0, 0, 0));
    }
  }
}

TEST(TraceModel, PolygonTwoSided) {
  const Vec3 square[4] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  auto t = TraceModel::polygon(square);
  ASSERT_TRUE(t.ok());
  EXPECT_FALSE(t->isConvex());
  EXPECT_EQ(t->numVertices(), 4);
  EXPECT_EQ(t->numEdges(), 4);
  EXPECT_EQ(t->numPolygons(), 2);
  EXPECT_EQ(t->polygon(0).normal, Vec3(0, 0, 1));
  EXPECT_EQ(t->polygon(1).normal, Vec3(0, 0, -1));
  EXPECT_EQ(t->polygon(1).edges[0], -4);
  EXPECT_EQ(t->offset(), Vec3(5, 5, 0));
  EXPECT_EQ(t->edge(1).normal, Vec3(0, -1, 0));  // outward in the plane
  EXPECT_EQ(t->checkInvariants(), "");
}

TEST(TraceModel, PolygonVolume) {
  const Vec3 tri[3] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  auto t = TraceModel::polygonVolume(tri, 4);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->numVertices(), 6);
  EXPECT_EQ(t->numEdges(), 9);
  EXPECT_EQ(t->numPolygons(), 5);
  expectClosedConvexSolid(*t);
  EXPECT_EQ(t->bounds(), Bounds({0, 0, -4}, {10, 10, 0}));
  EXPECT_NEAR(t->massProperties(1).volume, 200.0f, 1e-3f);
}

TEST(TraceModel, ConvexHullDropsInteriorPoints) {
  std::vector<Vec3> pts = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {1, 1, 1}, {2, 0, 0}};
  auto t = TraceModel::convexHull(pts);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->shape(), TrmShape::Custom);
  EXPECT_EQ(t->numVertices(), 4);  // (1,1,1) is inside, (2,0,0) on an edge
  EXPECT_EQ(t->numEdges(), 6);
  EXPECT_EQ(t->numPolygons(), 4);
  expectClosedConvexSolid(*t);
  EXPECT_NEAR(t->massProperties(1).volume, 64.0f / 6, 1e-3f);
}

TEST(TraceModel, ConvexHullOfACubeMergesCoplanarFaces) {
  std::vector<Vec3> pts;
  for (int i = 0; i < 8; ++i) pts.push_back({float(i & 1) * 8, float((i >> 1) & 1) * 8, float(i >> 2) * 8});
  pts.push_back({4, 4, 8});  // a point in the middle of the top face
  auto t = TraceModel::convexHull(pts);
  ASSERT_TRUE(t.ok());
  EXPECT_EQ(t->numVertices(), 8);
  EXPECT_EQ(t->numEdges(), 12);
  EXPECT_EQ(t->numPolygons(), 6);
  expectClosedConvexSolid(*t);
}

TEST(TraceModel, RandomHullsAreValid) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-50, 50);
  for (int i = 0; i < 30; ++i) {
    std::vector<Vec3> pts;
    for (int k = 0; k < 8; ++k) pts.push_back({u(rng), u(rng), u(rng)});
    auto t = TraceModel::convexHull(pts);
    if (!t.ok()) {  // random hulls may exceed the polygon/edge limits
      EXPECT_NE(t.error().message.find("at most"), std::string::npos) << t.error().message;
      continue;
    }
    expectClosedConvexSolid(*t);
  }
}

TEST(TraceModel, PointShape) {
  const TraceModel p = TraceModel::point();
  EXPECT_TRUE(p.isPoint());
  EXPECT_EQ(p.numVertices(), 1);
  EXPECT_EQ(p.numEdges(), 0);
  EXPECT_EQ(p.numPolygons(), 0);
  EXPECT_EQ(p.bounds(), Bounds({0, 0, 0}, {0, 0, 0}));
  // a box of zero size on every axis is a point at that place
  auto z = TraceModel::box({{1, 2, 3}, {1, 2, 3}});
  ASSERT_TRUE(z.ok());
  EXPECT_TRUE(z->isPoint());
  EXPECT_EQ(z->vertex(0), Vec3(1, 2, 3));
}

TEST(TraceModel, MassPropertiesOfABox) {
  auto t = TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  ASSERT_TRUE(t.ok());
  const MassProperties mp = t->massProperties(2);
  EXPECT_NEAR(mp.volume, 32 * 32 * 72, 1e-2f);
  EXPECT_NEAR(mp.mass, 2 * 32 * 32 * 72, 1e-1f);
  EXPECT_NEAR(mp.centerOfMass.z, 36, 1e-4f);
  // I_xx = m (h_y^2 + h_z^2) / 12 with full side lengths
  const float m = mp.mass;
  EXPECT_NEAR(mp.inertiaTensor[0][0] / (m * (32 * 32 + 72 * 72) / 12.0f), 1.0f, 1e-5f);
  EXPECT_NEAR(mp.inertiaTensor[2][2] / (m * (32 * 32 + 32 * 32) / 12.0f), 1.0f, 1e-5f);
  EXPECT_NEAR(mp.inertiaTensor[0][1], 0.0f, 1e-2f);
}

TEST(TraceModel, MassPropertiesOfPrismsAndPyramids) {
  const Bounds b{{-10, -10, 0}, {10, 10, 30}};
  for (int n : {3, 6, 10}) {
    // regular n-gon of circumradius 10: area n/2 r^2 sin(2 pi / n)
    const double area = n / 2.0 * 100 * std::sin(2 * std::numbers::pi / n);
    EXPECT_NEAR(TraceModel::cylinder(b, n)->massProperties(1).volume / (area * 30), 1.0, 1e-5);
    EXPECT_NEAR(TraceModel::cone(b, n)->massProperties(1).volume / (area * 30 / 3), 1.0, 1e-5);
    EXPECT_NEAR(TraceModel::cone(b, n)->massProperties(1).centerOfMass.z, 30.0 / 4, 1e-4);
  }
  // bone: two tetrahedra over a triangle of area w * 0.75w / 2
  auto bone = TraceModel::bone(40, 8);
  EXPECT_NEAR(bone->massProperties(1).volume, 8 * 6 / 2.0 * 40 / 3, 1e-3);
  // octahedron of half-size h: 4/3 h^3 for a regular one
  EXPECT_NEAR(TraceModel::octahedron({{-3, -3, -3}, {3, 3, 3}})->massProperties(1).volume, 4.0 / 3 * 27,
              1e-3);
  // regular dodecahedron of circumradius R: edge a = 4R/(sqrt3 (1+sqrt5)), V = (15+7 sqrt5)/4 a^3
  const double R = 10, a = 4 * R / (std::sqrt(3.0) * (1 + std::sqrt(5.0)));
  const auto dod = TraceModel::dodecahedron({{-10, -10, -10}, {10, 10, 10}});
  // scaled to the bounds: the extent along an axis is R * kC, so rescale
  const double scale = 1 / 0.9341723589729214;
  EXPECT_NEAR(dod->massProperties(1).volume / ((15 + 7 * std::sqrt(5.0)) / 4 * std::pow(a * scale, 3)), 1.0,
              1e-4);
}

TEST(TraceModel, TranslateAndRotateKeepTheShapeValid) {
  auto t = TraceModel::cylinder({{-8, -8, 0}, {8, 8, 40}}, 7);
  ASSERT_TRUE(t.ok());
  TraceModel moved = *t;
  moved.translate({100, -50, 3});
  expectClosedConvexSolid(moved);
  EXPECT_EQ(moved.offset(), t->offset() + Vec3(100, -50, 3));
  TraceModel turned = *t;
  const Mat3 axis = Mat3::fromAngles(30, 45, 60);
  turned.rotate(axis);
  expectClosedConvexSolid(turned);
  for (int i = 0; i < t->numVertices(); ++i) EXPECT_EQ(turned.vertex(i), t->vertex(i) * axis);
  EXPECT_FALSE(turned == *t);
  TraceModel copy = *t;
  EXPECT_TRUE(copy == *t);
  // 90 degrees about z (rows = axes): x goes to the first row
  TraceModel box = *TraceModel::box({{0, 0, 0}, {10, 20, 30}});
  box.rotate(Mat3{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}});
  EXPECT_EQ(box.bounds(), Bounds({-20, 0, 0}, {0, 10, 30}));
  expectClosedConvexSolid(box);
}

// The packed copies a query's set-up reads (polygonNormal, polygonPlaneVertex,
// edgeVertex, the edge and vertex bits) match the features, for every shape
// and after turning (which changes the normals).
void expectPackedFeatures(const TraceModel& t) {
  for (int i = 0; i < t.numPolygons(); ++i) {
    const TrmPolygon& p = t.polygon(i);
    EXPECT_EQ(t.polygonNormal(i), p.normal) << "polygon " << i;
    EXPECT_EQ(t.polygonPlaneVertex(i), t.edge(std::abs(p.edges[0])).v[0]) << "polygon " << i;
    std::uint64_t edgeBits = 0;
    std::uint32_t vertexBits = 0;
    for (int j = 0; j < p.numEdges; ++j) {
      edgeBits |= std::uint64_t(1) << std::abs(p.edges[std::size_t(j)]);
      vertexBits |= std::uint32_t(1) << p.startVertex(t, j);
    }
    EXPECT_EQ(t.polygonEdgeBits(i), edgeBits) << "polygon " << i;
    EXPECT_EQ(t.polygonVertexBits(i), vertexBits) << "polygon " << i;
  }
  for (int e = 1; e <= t.numEdges(); ++e) {
    EXPECT_EQ(t.edgeVertex(e, 0), t.edge(e).v[0]) << "edge " << e;
    EXPECT_EQ(t.edgeVertex(e, 1), t.edge(e).v[1]) << "edge " << e;
  }
}

TEST(TraceModel, PackedFeaturesMatchTheShape) {
  const Bounds b{{-8, -12, 0}, {8, 12, 40}};
  const std::vector<Vec3> square{{0, 0, 0}, {16, 0, 0}, {16, 16, 0}, {0, 16, 0}};
  for (const Result<TraceModel>& t :
       {TraceModel::box(b), TraceModel::octahedron(b), TraceModel::dodecahedron(b),
        TraceModel::cylinder(b, 7), TraceModel::cone(b, 5), TraceModel::bone(40, 10),
        TraceModel::polygon(square), TraceModel::polygonVolume(square, 4)}) {
    ASSERT_TRUE(t.ok());
    SCOPED_TRACE(t->describe());
    expectPackedFeatures(*t);
    TraceModel turned = *t;
    turned.rotate(Mat3::fromAngles(30, 45, 60));
    turned.translate({5, -3, 2});
    expectPackedFeatures(turned);
    EXPECT_NE(turned.polygonNormal(0), t->polygonNormal(0));
    EXPECT_EQ(turned.checkInvariants(), "");
  }
}

TEST(TraceModel, ParseMatchesFactories) {
  EXPECT_TRUE(*TraceModel::parse("box:-16,-16,0,16,16,72") ==
              *TraceModel::box({{-16, -16, 0}, {16, 16, 72}}));
  EXPECT_TRUE(*TraceModel::parse("cylinder:8:-10,-10,0,10,10,20") ==
              *TraceModel::cylinder({{-10, -10, 0}, {10, 10, 20}}, 8));
  EXPECT_TRUE(*TraceModel::parse("cone:5:-10,-10,0,10,10,20") ==
              *TraceModel::cone({{-10, -10, 0}, {10, 10, 20}}, 5));
  EXPECT_TRUE(*TraceModel::parse("bone:43,27") == *TraceModel::bone(43, 27));
  EXPECT_TRUE(*TraceModel::parse("octahedron:-1,-1,-1,1,1,1") ==
              *TraceModel::octahedron({{-1, -1, -1}, {1, 1, 1}}));
  EXPECT_TRUE(TraceModel::parse("point")->isPoint());
  EXPECT_TRUE(TraceModel::parse("dodecahedron:2,2,2,2,2,2")->isPoint());
  auto poly = TraceModel::parse("polygon:16,0,0;-0.0625,16,0;-16,-0.0625,0;0,-16,0");
  ASSERT_TRUE(poly.ok()) << poly.error().message;
  EXPECT_EQ(poly->numVertices(), 4);
  EXPECT_TRUE(TraceModel::parse("polygonvolume:2:0,0,0;10,0,0;10,10,0").ok());
  EXPECT_TRUE(TraceModel::parse("hull:0,0,0;1,0,0;0,1,0;0,0,1").ok());
}

TEST(TraceModel, Rejections) {
  auto expectError = [](const Result<TraceModel>& r, const char* needle) {
    ASSERT_FALSE(r.ok()) << needle;
    EXPECT_NE(r.error().message.find(needle), std::string::npos) << r.error().message;
  };
  expectError(TraceModel::box({{0, 0, 0}, {1, -1, 1}}), "max below min on y");
  expectError(TraceModel::octahedron({{0, 0, 0}, {1, 1, 0}}), "zero size on z");
  expectError(TraceModel::dodecahedron({{0, 0, 0}, {-1, 1, 1}}), "max below min on x");
  expectError(TraceModel::cylinder({{0, 0, 0}, {1, 1, 1}}, 2), "3 to 10 sides");
  expectError(TraceModel::cylinder({{0, 0, 0}, {1, 1, 1}}, 11), "3 to 10 sides");
  expectError(TraceModel::cone({{0, 0, 0}, {1, 1, 1}}, 16), "3 to 15 sides");
  expectError(TraceModel::cone({{0, 0, 0}, {1, 1, 1}}, 1), "3 to 15 sides");
  expectError(TraceModel::bone(0, 5), "length and width");
  expectError(TraceModel::bone(5, -1), "length and width");
  const Vec3 two[2] = {{0, 0, 0}, {1, 0, 0}};
  expectError(TraceModel::polygon(two), "at least 3");
  const Vec3 collinear[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  expectError(TraceModel::polygon(collinear), "zero normal");
  const Vec3 bent[4] = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 5}};
  expectError(TraceModel::polygon(bent), "not planar");
  const Vec3 dart[4] = {{0, 0, 0}, {10, 0, 0}, {2, 2, 0}, {0, 10, 0}};
  expectError(TraceModel::polygon(dart), "not convex");
  const Vec3 repeated[4] = {{0, 0, 0}, {10, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  expectError(TraceModel::polygon(repeated), "coincide");
  std::vector<Vec3> many;
  for (int i = 0; i < 17; ++i) {
    const float a = float(i) * 2 * std::numbers::pi_v<float> / 17;
    many.push_back({std::cos(a) * 10, std::sin(a) * 10, 0});
  }
  expectError(TraceModel::polygon(many), "at most 16");
  many.resize(11);
  expectError(TraceModel::polygonVolume(std::span(many).first(11), 2), "at most 10");
  const Vec3 tri[3] = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}};
  expectError(TraceModel::polygonVolume(tri, 0), "thickness");
  const Vec3 flat[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  expectError(TraceModel::convexHull(flat), "coplanar");
  std::vector<Vec3> sphere;  // 60 points on a sphere: far more than 32 hull vertices
  for (int i = 0; i < 60; ++i) {
    const float z = -1 + 2 * (float(i) + 0.5f) / 60, r = std::sqrt(1 - z * z), phi = float(i) * 2.39996f;
    sphere.push_back(Vec3{r * std::cos(phi), r * std::sin(phi), z} * 100);
  }
  expectError(TraceModel::convexHull(sphere), "at most");
  expectError(TraceModel::convexHull(std::vector<Vec3>(300, Vec3{})), "at most 256");
  expectError(TraceModel::parse("box:1,2,3"), "needs 6 numbers");
  expectError(TraceModel::parse("box:1,2,3,4,5,nan"), "bad number");
  expectError(TraceModel::parse("box:1,2,3,4,5,1e99"), "bad number");
  expectError(TraceModel::parse("sphere:1,2,3,4,5,6"), "unknown trace model kind");
  expectError(TraceModel::parse("cylinder:x:1,2,3,4,5,6"), "bad side count");
  expectError(TraceModel::parse("capsule"), "unknown trace model");
}
