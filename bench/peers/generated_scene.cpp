// generated_scene.cpp: a deterministic scene of ~50 000 triangles, the kind
// a game level built from meshes has: a height-field terrain, ~2000 crates
// (half axis-aligned, half turned and tilted), staircases and ramps.
#include <cmath>
#include <numbers>

#include "peers.h"

namespace peers {

namespace {

constexpr std::uint64_t kSeed = 20261128;
/// Terrain: kCells x kCells quads (two triangles each) over kExtent units.
constexpr int kCells = 110;
constexpr double kExtent = 8192;
constexpr int kCrates = 2000;
constexpr int kStaircases = 6;
constexpr int kStepsPerStaircase = 16;
constexpr int kRamps = 8;

struct P {
  double x, y, z;
};

struct Builder {
  Scene& scene;
  std::uint32_t vertex(const P& p) {
    scene.positions.insert(scene.positions.end(), {float(p.x), float(p.y), float(p.z)});
    return std::uint32_t(scene.numVertices() - 1);
  }
  void triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    scene.indices.insert(scene.indices.end(), {a, b, c});
  }
  /// A quad a b c d counter-clockwise seen from the front.
  void quad(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    triangle(a, b, c);
    triangle(a, c, d);
  }
  /// A box: centre, half extents, turned by yaw (about z) then pitch (about x).
  void box(const P& c, const P& h, double yaw, double pitch) {
    const double cy = std::cos(yaw), sy = std::sin(yaw), cp = std::cos(pitch), sp = std::sin(pitch);
    std::uint32_t v[8];
    for (int i = 0; i < 8; ++i) {
      const double x = (i & 1 ? h.x : -h.x), y0 = (i & 2 ? h.y : -h.y), z0 = (i & 4 ? h.z : -h.z);
      const double y = y0 * cp - z0 * sp, z = y0 * sp + z0 * cp;
      v[i] = vertex({c.x + x * cy - y * sy, c.y + x * sy + y * cy, c.z + z});
    }
    quad(v[0], v[2], v[3], v[1]);  // -z
    quad(v[4], v[5], v[7], v[6]);  // +z
    quad(v[0], v[1], v[5], v[4]);  // -y
    quad(v[2], v[6], v[7], v[3]);  // +y
    quad(v[0], v[4], v[6], v[2]);  // -x
    quad(v[1], v[3], v[7], v[5]);  // +x
  }
};

double terrainHeight(double x, double y) {
  return 180 * std::sin(x * 0.0011) * std::cos(y * 0.0009) + 60 * std::sin((x + 2 * y) * 0.0041) +
         25 * std::cos((3 * x - y) * 0.0093);
}

}  // namespace

Scene generatedScene() {
  Scene scene;
  Builder b{scene};
  Rng rng(kSeed);
  const double cell = kExtent / kCells, x0 = -kExtent / 2;
  // Terrain, with a little noise on each height.
  std::vector<std::uint32_t> grid;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const double x = x0 + i * cell, y = x0 + j * cell;
      grid.push_back(b.vertex({x, y, terrainHeight(x, y) + rng.uniform(-4, 4)}));
    }
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      const auto at = [&](int di, int dj) { return grid[std::size_t((j + dj) * (kCells + 1) + i + di)]; };
      b.quad(at(0, 0), at(1, 0), at(1, 1), at(0, 1));
    }
  // Crates standing on (and sunk a little into) the terrain, some stacked.
  for (int k = 0; k < kCrates; ++k) {
    const double x = rng.uniform(-0.48, 0.48) * kExtent, y = rng.uniform(-0.48, 0.48) * kExtent;
    const P h{rng.uniform(8, 48), rng.uniform(8, 48), rng.uniform(8, 48)};
    const bool turned = k % 2 == 1;
    const double yaw = turned ? rng.uniform(0, std::numbers::pi) : 0;
    const double pitch = turned ? rng.uniform(-0.4, 0.4) : 0;
    const double stack = k % 7 == 0 ? 2 * h.z : 0;
    b.box({x, y, terrainHeight(x, y) + h.z - 4 + stack}, h, yaw, pitch);
  }
  // Staircases: steps of 16 high, 24 deep, 128 wide, each a box.
  for (int s = 0; s < kStaircases; ++s) {
    const double x = rng.uniform(-0.4, 0.4) * kExtent, y = rng.uniform(-0.4, 0.4) * kExtent;
    const double yaw = rng.uniform(0, 2 * std::numbers::pi), base = terrainHeight(x, y) - 8;
    for (int k = 0; k < kStepsPerStaircase; ++k) {
      const double along = 24 * k, hz = 8 * (k + 1);
      b.box({x + along * std::cos(yaw), y + along * std::sin(yaw), base + hz}, {12, 64, hz}, yaw, 0);
    }
  }
  // Ramps: wedges 256 long, 128 wide, rising 96 (a slope of ~20 degrees).
  for (int r = 0; r < kRamps; ++r) {
    const double x = rng.uniform(-0.4, 0.4) * kExtent, y = rng.uniform(-0.4, 0.4) * kExtent;
    const double yaw = rng.uniform(0, 2 * std::numbers::pi), z = terrainHeight(x, y) - 8;
    const double c = std::cos(yaw), s = std::sin(yaw);
    const auto at = [&](double u, double v, double h) {
      return b.vertex({x + u * c - v * s, y + u * s + v * c, z + h});
    };
    const std::uint32_t a0 = at(0, -64, 0), a1 = at(0, 64, 0), b0 = at(256, -64, 0), b1 = at(256, 64, 0);
    const std::uint32_t t0 = at(256, -64, 96), t1 = at(256, 64, 96);
    b.quad(a0, a1, b1, b0);  // bottom
    b.quad(a0, t0, t1, a1);  // slope
    b.quad(b0, b1, t1, t0);  // back
    b.triangle(a0, b0, t0);  // sides
    b.triangle(a1, t1, b1);
  }
  scene.name = "generated scene (terrain, " + std::to_string(kCrates) + " crates, " +
               std::to_string(kStaircases) + " staircases, " + std::to_string(kRamps) + " ramps)";
  scene.computeBounds();
  return scene;
}

}  // namespace peers
