// peers.h: what the parts of cmkit_peers share. Plain data only (no cmkit,
// Jolt, Bullet or Embree types), because the Jolt peer is compiled with
// Jolt's own defines and ISA flags and must not see cmkit's headers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace peers {

/// A triangle soup: xyz per vertex, three indices per triangle
/// (counter-clockwise seen from the front; every engine gets it two-sided).
struct Scene {
  std::string name;
  std::vector<float> positions;
  std::vector<std::uint32_t> indices;
  double boundsMin[3] = {0, 0, 0};
  double boundsMax[3] = {0, 0, 0};

  std::size_t numVertices() const { return positions.size() / 3; }
  std::size_t numTriangles() const { return indices.size() / 3; }
  /// Sets the bounds from the positions.
  void computeBounds();
};

/// The moving shape as every engine gets it. A point when `point`; else a
/// convex polytope whose vertices `hull` (xyz, relative to the shape's
/// origin, which is what moves from start to end) are turned by `axis`
/// (rows = the shape's axes: world offset = local * axis, cmkit's
/// convention). A box is also given as centre + half extents (local frame).
struct ShapeSpec {
  std::string name;
  bool point = true;
  bool box = false;
  float centre[3] = {0, 0, 0};
  float halfExtents[3] = {0, 0, 0};
  std::vector<float> hull;
  float axis[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// The longest of cmkit's edge normals of the shape (TrmEdge::normal: the
  /// bisector of the edge's faces scaled to a component of 1 along each;
  /// sqrt(2) for a box), for the reference's model of cmkit's clip epsilon.
  float edgeNormalMax = 1;
};

/// A small deterministic generator (splitmix64): the same scene and queries
/// on every machine and standard library.
struct Rng {
  std::uint64_t state;
  explicit Rng(std::uint64_t seed) : state(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1).
  double uniform() { return double(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
};

/// One move of the shape's origin.
struct Query {
  float start[3];
  float end[3];
};

/// What an engine answers for a query: the fraction of the move at the
/// first contact, or kMiss.
inline constexpr float kMiss = 2.0f;

/// A peer engine. build() makes its structure of the scene's triangles
/// (timed by the caller: everything it does counts); prepare() makes the
/// moving shape (not timed); sweep() and rays() answer every query.
class Peer {
 public:
  virtual ~Peer() = default;
  virtual const char* name() const = 0;
  virtual bool hasSweeps() const = 0;
  virtual void build(const Scene& scene) = 0;
  virtual void prepare(const ShapeSpec& shape) = 0;
  virtual void sweep(std::span<const Query> queries, float* fractions) = 0;
  virtual void rays(std::span<const Query> queries, float* fractions) = 0;
};

/// The peers compiled in (each returns nullptr when it was not).
bool joltCompiledIn();
bool embreeCompiledIn();
std::unique_ptr<Peer> makeJoltPeer();
std::unique_ptr<Peer> makeBulletPeer();
std::unique_ptr<Peer> makeEmbreePeer();

/// The triangles of lt4's world model (or another map's): every polygon of
/// the world model matching solid|playerclip as a fan. Empty on error (printed).
Scene loadMapScene(const std::string& mapPath);
/// The generated scene: terrain, crates, staircases and ramps (fixed seed).
Scene generatedScene();

/// The old program's section: the speed test's moves on a map through
/// cmkit, Bullet and Embree, and the batch throughput. Returns an exit code.
int runSpeedTestSection(const std::string& mapPath, int times, int passes);

}  // namespace peers
