// peer_bullet.cpp: Bullet (Debian's libbullet-dev, single precision) as a
// peer. The scene: a btBvhTriangleMeshShape (quantized AABB compression) of
// a btTriangleMesh, margin 0, in a btCollisionWorld. Sweeps:
// convexSweepTest with a btBoxShape or a btConvexHullShape (margins 0) and a
// ClosestConvexResultCallback; rays: rayTest with a
// ClosestRayResultCallback. Bullet's triangles collide from both sides. The
// answer is m_closestHitFraction.
#include <btBulletCollisionCommon.h>

#include "peers.h"

namespace peers {

namespace {

class BulletPeer final : public Peer {
 public:
  BulletPeer() : dispatcher_(&config_), world_(&dispatcher_, &broadphase_, &config_) {}
  ~BulletPeer() override { clear(); }
  const char* name() const override { return "Bullet"; }
  bool hasSweeps() const override { return true; }

  void build(const Scene& scene) override {
    clear();
    mesh_ = std::make_unique<btTriangleMesh>();
    const auto at = [&](std::uint32_t i) {
      return btVector3(scene.positions[3 * i], scene.positions[3 * i + 1], scene.positions[3 * i + 2]);
    };
    for (std::size_t t = 0; t < scene.numTriangles(); ++t)
      mesh_->addTriangle(at(scene.indices[3 * t]), at(scene.indices[3 * t + 1]),
                         at(scene.indices[3 * t + 2]));
    shape_ = std::make_unique<btBvhTriangleMeshShape>(mesh_.get(), true);
    shape_->setMargin(0);
    object_ = std::make_unique<btCollisionObject>();
    object_->setCollisionShape(shape_.get());
    world_.addCollisionObject(object_.get());
    world_.updateAabbs();
  }

  void prepare(const ShapeSpec& s) override {
    cast_.reset();
    if (s.point) return;
    // btMatrix3x3 maps local to world: its columns are the shape's axes.
    const float* a = s.axis;
    basis_.setValue(a[0], a[3], a[6], a[1], a[4], a[7], a[2], a[5], a[8]);
    offset_ = btVector3(0, 0, 0);
    if (s.box) {
      cast_ = std::make_unique<btBoxShape>(btVector3(s.halfExtents[0], s.halfExtents[1], s.halfExtents[2]));
      offset_ = basis_ * btVector3(s.centre[0], s.centre[1], s.centre[2]);
    } else {
      auto hull = std::make_unique<btConvexHullShape>();
      for (std::size_t i = 0; i + 2 < s.hull.size(); i += 3)
        hull->addPoint(btVector3(s.hull[i], s.hull[i + 1], s.hull[i + 2]), false);
      hull->recalcLocalAabb();
      cast_ = std::move(hull);
    }
    cast_->setMargin(0);
  }

  void sweep(std::span<const Query> queries, float* fractions) override {
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      const btTransform from(basis_, btVector3(q.start[0], q.start[1], q.start[2]) + offset_);
      const btTransform to(basis_, btVector3(q.end[0], q.end[1], q.end[2]) + offset_);
      btCollisionWorld::ClosestConvexResultCallback cb(from.getOrigin(), to.getOrigin());
      world_.convexSweepTest(cast_.get(), from, to, cb, 0);
      fractions[i] = cb.hasHit() ? cb.m_closestHitFraction : kMiss;
    }
  }

  void rays(std::span<const Query> queries, float* fractions) override {
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      const btVector3 from(q.start[0], q.start[1], q.start[2]), to(q.end[0], q.end[1], q.end[2]);
      btCollisionWorld::ClosestRayResultCallback cb(from, to);
      world_.rayTest(from, to, cb);
      fractions[i] = cb.hasHit() ? cb.m_closestHitFraction : kMiss;
    }
  }

 private:
  void clear() {
    if (object_) world_.removeCollisionObject(object_.get());
    object_.reset();
    shape_.reset();
    mesh_.reset();
  }

  btDefaultCollisionConfiguration config_;
  btCollisionDispatcher dispatcher_;
  btDbvtBroadphase broadphase_;
  btCollisionWorld world_;
  std::unique_ptr<btTriangleMesh> mesh_;
  std::unique_ptr<btBvhTriangleMeshShape> shape_;
  std::unique_ptr<btCollisionObject> object_;
  std::unique_ptr<btConvexShape> cast_;
  btMatrix3x3 basis_ = btMatrix3x3::getIdentity();
  btVector3 offset_{0, 0, 0};
};

}  // namespace

std::unique_ptr<Peer> makeBulletPeer() { return std::make_unique<BulletPeer>(); }

}  // namespace peers
