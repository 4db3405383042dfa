// peer_jolt.cpp: Jolt Physics as a peer. The only file that includes Jolt's
// headers: CMake compiles it with the defines and ISA flags of the installed
// Jolt (Jolt::Jolt), and it sees no cmkit header (peers.h is plain data).
//
// The scene: a MeshShape of the triangles (MeshShapeSettings of the indexed
// triangles, then Create()). Sweeps: a BoxShape (convex radius 0) or a
// ConvexHullShape of the hull's vertices (convex radius 0), cast with
// CollisionDispatch::sCastShapeVsShapeLocalSpace against the mesh at the
// origin, back faces colliding, into a ClosestHitCollisionCollector. Rays:
// MeshShape::CastRay. The answer is Jolt's fraction of the move.
#ifdef CMKIT_HAVE_JOLT

// clang-format off
#include <Jolt/Jolt.h>
// clang-format on
#include <Jolt/Core/Factory.h>
#include <Jolt/Physics/Collision/CastResult.h>
#include <Jolt/Physics/Collision/CollisionCollectorImpl.h>
#include <Jolt/Physics/Collision/CollisionDispatch.h>
#include <Jolt/Physics/Collision/RayCast.h>
#include <Jolt/Physics/Collision/Shape/BoxShape.h>
#include <Jolt/Physics/Collision/Shape/ConvexHullShape.h>
#include <Jolt/Physics/Collision/Shape/MeshShape.h>
#include <Jolt/Physics/Collision/ShapeCast.h>
#include <Jolt/Physics/Collision/ShapeFilter.h>
#include <Jolt/RegisterTypes.h>

#include <cstdio>

#include "peers.h"

namespace peers {

namespace {

class JoltPeer final : public Peer {
 public:
  JoltPeer() {
    JPH::RegisterDefaultAllocator();
    JPH::Factory::sInstance = new JPH::Factory();
    JPH::RegisterTypes();
    settings_.SetBackFaceMode(JPH::EBackFaceMode::CollideWithBackFaces);
  }
  ~JoltPeer() override {
    mesh_ = nullptr;
    shape_ = nullptr;
    JPH::UnregisterTypes();
    delete JPH::Factory::sInstance;
    JPH::Factory::sInstance = nullptr;
  }
  const char* name() const override { return "Jolt"; }
  bool hasSweeps() const override { return true; }

  void build(const Scene& scene) override {
    JPH::VertexList vertices;
    vertices.reserve(scene.numVertices());
    for (std::size_t i = 0; i < scene.numVertices(); ++i)
      vertices.push_back(
          JPH::Float3(scene.positions[3 * i], scene.positions[3 * i + 1], scene.positions[3 * i + 2]));
    JPH::IndexedTriangleList triangles;
    triangles.reserve(scene.numTriangles());
    for (std::size_t t = 0; t < scene.numTriangles(); ++t)
      triangles.push_back(
          JPH::IndexedTriangle(scene.indices[3 * t], scene.indices[3 * t + 1], scene.indices[3 * t + 2]));
    JPH::MeshShapeSettings settings(std::move(vertices), std::move(triangles));
    JPH::ShapeSettings::ShapeResult result = settings.Create();
    if (result.HasError()) {
      std::fprintf(stderr, "Jolt: MeshShape: %s\n", result.GetError().c_str());
      mesh_ = nullptr;
      return;
    }
    mesh_ = result.Get();
  }

  void prepare(const ShapeSpec& s) override {
    shape_ = nullptr;
    offset_ = JPH::Vec3::sZero();
    if (s.point) return;
    // Jolt's rotation: columns = the shape's axes (cmkit's rows).
    const float* a = s.axis;
    rotation_ = JPH::Mat44(JPH::Vec4(a[0], a[1], a[2], 0), JPH::Vec4(a[3], a[4], a[5], 0),
                           JPH::Vec4(a[6], a[7], a[8], 0), JPH::Vec4(0, 0, 0, 1));
    if (s.box) {
      shape_ = new JPH::BoxShape(JPH::Vec3(s.halfExtents[0], s.halfExtents[1], s.halfExtents[2]), 0.0f);
      offset_ = rotation_.Multiply3x3(JPH::Vec3(s.centre[0], s.centre[1], s.centre[2]));
    } else {
      JPH::Array<JPH::Vec3> points;
      for (std::size_t i = 0; i + 2 < s.hull.size(); i += 3)
        points.push_back(JPH::Vec3(s.hull[i], s.hull[i + 1], s.hull[i + 2]));
      JPH::ConvexHullShapeSettings hull(points, 0.0f);
      JPH::ShapeSettings::ShapeResult result = hull.Create();
      if (result.HasError()) {
        std::fprintf(stderr, "Jolt: ConvexHullShape: %s\n", result.GetError().c_str());
        return;
      }
      shape_ = result.Get();
    }
  }

  void sweep(std::span<const Query> queries, float* fractions) override {
    if (!mesh_ || !shape_) {
      for (std::size_t i = 0; i < queries.size(); ++i) fractions[i] = kMiss;
      return;
    }
    const JPH::SubShapeIDCreator ids;
    const JPH::ShapeFilter filter;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      const JPH::Vec3 start(q.start[0], q.start[1], q.start[2]), end(q.end[0], q.end[1], q.end[2]);
      JPH::Mat44 transform = rotation_;
      transform.SetTranslation(start + offset_);
      const JPH::ShapeCast cast =
          JPH::ShapeCast::sFromWorldTransform(shape_, JPH::Vec3::sOne(), transform, end - start);
      JPH::ClosestHitCollisionCollector<JPH::CastShapeCollector> collector;
      JPH::CollisionDispatch::sCastShapeVsShapeLocalSpace(cast, settings_, mesh_, JPH::Vec3::sOne(), filter,
                                                          JPH::Mat44::sIdentity(), ids, ids, collector);
      fractions[i] = collector.HadHit() ? collector.mHit.mFraction : kMiss;
    }
  }

  void rays(std::span<const Query> queries, float* fractions) override {
    const JPH::SubShapeIDCreator ids;
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      const JPH::Vec3 start(q.start[0], q.start[1], q.start[2]), end(q.end[0], q.end[1], q.end[2]);
      JPH::RayCastResult hit;
      fractions[i] =
          mesh_ && mesh_->CastRay(JPH::RayCast{start, end - start}, ids, hit) ? hit.mFraction : kMiss;
    }
  }

 private:
  JPH::ShapeCastSettings settings_;
  JPH::RefConst<JPH::Shape> mesh_;
  JPH::RefConst<JPH::Shape> shape_;
  JPH::Mat44 rotation_ = JPH::Mat44::sIdentity();
  JPH::Vec3 offset_ = JPH::Vec3::sZero();
};

}  // namespace

bool joltCompiledIn() { return true; }
std::unique_ptr<Peer> makeJoltPeer() { return std::make_unique<JoltPeer>(); }

}  // namespace peers

#else

#include "peers.h"

namespace peers {
bool joltCompiledIn() { return false; }
std::unique_ptr<Peer> makeJoltPeer() { return nullptr; }
}  // namespace peers

#endif
