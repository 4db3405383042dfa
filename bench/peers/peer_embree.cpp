// peer_embree.cpp: Embree 3 (Debian's libembree-dev) as a peer for rays: a
// scene of one triangle geometry (the same vertices and indices), committed
// with the default build quality; rays through rtcIntersect1 with t in
// [0, 1] spanning the move, so tfar is the fraction. Embree's triangles are
// hit from both sides. It has no shape sweeps.
#include "peers.h"

#ifdef CMKIT_HAVE_EMBREE
#include <embree3/rtcore.h>

#include <algorithm>

namespace peers {

namespace {

class EmbreePeer final : public Peer {
 public:
  EmbreePeer() : device_(rtcNewDevice(nullptr)) { rtcInitIntersectContext(&context_); }
  ~EmbreePeer() override {
    if (scene_) rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  const char* name() const override { return "Embree"; }
  bool hasSweeps() const override { return false; }

  void build(const Scene& scene) override {
    if (scene_) rtcReleaseScene(scene_);
    scene_ = rtcNewScene(device_);
    RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.numVertices()));
    std::copy(scene.positions.begin(), scene.positions.end(), vertices);
    auto* tris = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), scene.numTriangles()));
    std::copy(scene.indices.begin(), scene.indices.end(), tris);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene_, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene_);
  }

  void prepare(const ShapeSpec&) override {}
  void sweep(std::span<const Query> queries, float* fractions) override {
    std::fill(fractions, fractions + queries.size(), kMiss);
  }

  void rays(std::span<const Query> queries, float* fractions) override {
    for (std::size_t i = 0; i < queries.size(); ++i) {
      const Query& q = queries[i];
      RTCRayHit rh{};
      rh.ray.org_x = q.start[0];
      rh.ray.org_y = q.start[1];
      rh.ray.org_z = q.start[2];
      rh.ray.dir_x = q.end[0] - q.start[0];
      rh.ray.dir_y = q.end[1] - q.start[1];
      rh.ray.dir_z = q.end[2] - q.start[2];
      rh.ray.tnear = 0;
      rh.ray.tfar = 1;
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene_, &context_, &rh);
      fractions[i] = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID ? rh.ray.tfar : kMiss;
    }
  }

 private:
  RTCDevice device_;
  RTCScene scene_ = nullptr;
  RTCIntersectContext context_;
};

}  // namespace

bool embreeCompiledIn() { return true; }
std::unique_ptr<Peer> makeEmbreePeer() { return std::make_unique<EmbreePeer>(); }

}  // namespace peers

#else

namespace peers {
bool embreeCompiledIn() { return false; }
std::unique_ptr<Peer> makeEmbreePeer() { return nullptr; }
}  // namespace peers

#endif
