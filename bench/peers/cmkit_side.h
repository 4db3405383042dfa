// cmkit_side.h: cmkit as one engine of cmkit_peers, behind the same plain
// interface as the peers: the triangles as a mesh with one two-sided solid
// material (buildCollisionModelFromTriangles), sweeps through translate(),
// rays through RayIndex::cast().
#pragma once

#include <string>

#include <memory>
#include <span>

#include "peers.h"

namespace peers {

class CmkitEngine {
 public:
  CmkitEngine();
  ~CmkitEngine();
  /// Builds the collision model of the scene's triangles (with whatever
  /// the model's constructor makes); false on error (printed).
  bool buildModel(const Scene& scene);
  /// Builds the RayIndex of the model.
  void buildRayIndex();
  /// Whether the ray index uses the AVX2 node test.
  bool rayIndexUsesAvx2() const;
  /// The ray index's size: "N polygons, M nodes, K KB".
  std::string rayIndexSize() const;
  /// The model's memory (cmkit::modelMemory), for --verbose.
  std::string modelSize() const;
  /// The moving shape: a cmkit::TraceModel::parse spec ("point",
  /// "box:...", "cylinder:8:...") turned by `axis` (rows = the shape's
  /// axes). Fills `spec` with what the peers get. False on a bad spec.
  bool prepare(const char* trmSpec, const float (&axis)[9], ShapeSpec& spec);
  void sweep(std::span<const Query> queries, float* fractions);
  void rays(std::span<const Query> queries, float* fractions);

 private:
  struct State;
  std::unique_ptr<State> s_;
};

}  // namespace peers
