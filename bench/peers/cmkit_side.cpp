// cmkit_side.cpp: cmkit as an engine of cmkit_peers (cmkit_side.h).
#include "cmkit_side.h"

#include <algorithm>
#include <cstdio>

#include "cmkit/materials.h"
#include "cmkit/mesh.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/trace_model.h"

namespace peers {

namespace {
/// The one material of the mesh: two-sided (so both faces collide, as the
/// peers' triangles do) and solid (a declared material starts solid|opaque).
constexpr const char* kMaterial = "textures/peers/twosided";
constexpr std::uint32_t kMask = cmkit::contents::kSolid;
}  // namespace

struct CmkitEngine::State {
  cmkit::MaterialTable materials;
  cmkit::ModelPtr model;
  std::unique_ptr<cmkit::RayIndex> rays;
  cmkit::TraceModel trm = cmkit::TraceModel::point();
  cmkit::Mat3 axis;
  cmkit::QueryWork work;
};

CmkitEngine::CmkitEngine() : s_(std::make_unique<State>()) {
  s_->materials.addMtrText(std::string(kMaterial) + " { twosided }\n", "peers.mtr");
}

CmkitEngine::~CmkitEngine() = default;

bool CmkitEngine::buildModel(const Scene& scene) {
  cmkit::TriangleMesh mesh;
  mesh.positions.reserve(scene.numVertices());
  for (std::size_t i = 0; i < scene.numVertices(); ++i)
    mesh.positions.push_back(
        {scene.positions[3 * i], scene.positions[3 * i + 1], scene.positions[3 * i + 2]});
  mesh.surfaces.push_back({kMaterial, scene.indices});
  auto built = cmkit::buildCollisionModelFromTriangles(mesh, "peers", s_->materials);
  if (!built) {
    std::fprintf(stderr, "cmkit: %s\n", built.error().toString().c_str());
    return false;
  }
  s_->model = std::move(built->model);
  return true;
}

void CmkitEngine::buildRayIndex() { s_->rays = std::make_unique<cmkit::RayIndex>(*s_->model); }

bool CmkitEngine::rayIndexUsesAvx2() const { return s_->rays && s_->rays->usesAvx2(); }
std::string CmkitEngine::modelSize() const {
  if (!s_->model) return "none";
  const cmkit::ModelMemory m = cmkit::modelMemory(*s_->model);
  return std::to_string(m.arrays / 1024) + " KB of arrays, " + std::to_string(m.queryData / 1024) +
         " KB of query data";
}

std::string CmkitEngine::rayIndexSize() const {
  if (!s_->rays) return "none";
  return std::to_string(s_->rays->numPolygons()) + " polygons, " + std::to_string(s_->rays->numNodes()) +
         " nodes, " + std::to_string(s_->rays->memoryBytes() / 1024) + " KB";
}

bool CmkitEngine::prepare(const char* trmSpec, const float (&axis)[9], ShapeSpec& spec) {
  auto trm = cmkit::TraceModel::parse(trmSpec);
  if (!trm) {
    std::fprintf(stderr, "cmkit: %s: %s\n", trmSpec, trm.error().toString().c_str());
    return false;
  }
  s_->trm = *trm;
  s_->axis =
      cmkit::Mat3{{axis[0], axis[1], axis[2]}, {axis[3], axis[4], axis[5]}, {axis[6], axis[7], axis[8]}};
  spec.point = trm->isPoint();
  spec.box = trm->shape() == cmkit::TrmShape::Box;
  const cmkit::Bounds& b = trm->bounds();
  for (int k = 0; k < 3; ++k) {
    spec.centre[k] = (b.min[k] + b.max[k]) * 0.5f;
    spec.halfExtents[k] = (b.max[k] - b.min[k]) * 0.5f;
  }
  spec.hull.clear();
  for (const cmkit::Vec3& v : trm->vertices()) spec.hull.insert(spec.hull.end(), {v.x, v.y, v.z});
  for (int i = 0; i < 9; ++i) spec.axis[i] = axis[i];
  spec.edgeNormalMax = 1;
  for (int e = 1; e <= trm->numEdges(); ++e)
    spec.edgeNormalMax = std::max(spec.edgeNormalMax, float(trm->edge(e).normal.length()));
  return true;
}

void CmkitEngine::sweep(std::span<const Query> queries, float* fractions) {
  cmkit::TranslationQuery q;
  q.trm = &s_->trm;
  q.trmAxis = s_->axis;
  q.contentMask = kMask;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    q.start = {queries[i].start[0], queries[i].start[1], queries[i].start[2]};
    q.end = {queries[i].end[0], queries[i].end[1], queries[i].end[2]};
    const cmkit::TraceResult r = cmkit::translate(*s_->model, q, s_->work);
    fractions[i] = r.fraction < 1 ? float(r.fraction) : kMiss;
  }
}

void CmkitEngine::rays(std::span<const Query> queries, float* fractions) {
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const cmkit::Vec3 start{queries[i].start[0], queries[i].start[1], queries[i].start[2]};
    const cmkit::Vec3 end{queries[i].end[0], queries[i].end[1], queries[i].end[2]};
    const cmkit::RayHit h = s_->rays->cast({start, end, kMask});
    fractions[i] = h.hit() ? float(h.fraction) : kMiss;
  }
}

}  // namespace peers
