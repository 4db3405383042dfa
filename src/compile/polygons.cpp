// Windings -> polygons: vertex welding, edge sharing (the original's
// GetVertex, GetEdge, CreatePolygon and PolygonFromWinding).
#include <bit>
#include <climits>
#include <cmath>
#include <cstdlib>

#include "compile/builder.h"
#include "util/simd.h"

namespace cmkit::detail {

namespace {

/// (int)x as x86 converts it: out of range (or NaN) gives INT_MIN.
int truncateToInt(double x) {
  if (!(x > -2147483649.0 && x < 2147483648.0)) return INT_MIN;
  return static_cast<int>(x);
}

/// The hash cell of one coordinate (4-unit cells from the hash minimum).
int axisCell(Real c, Real mn, double offset) {
  const long long i = truncateToInt(static_cast<double>(c - mn) + offset);
  return static_cast<int>((i + 2) >> 2);
}

int combineCells(const int k[3], int hashSize) {
  const std::uint32_t key = static_cast<std::uint32_t>(k[0]) + 64u * static_cast<std::uint32_t>(k[1]) +
                            static_cast<std::uint32_t>(k[2]);
  return static_cast<int>(key & static_cast<std::uint32_t>(hashSize - 1));
}

/// std::floor without the library call the baseline instruction set makes
/// of it (no rounding instruction before SSE4.1), with the same value for
/// every input: truncation, one less below zero; 0 and -0 are their own
/// floor (truncation would lose the sign); from 2^23 in magnitude on, and
/// for infinities and NaN, std::floor itself.
Real floorOf(Real x) {
  constexpr Real kTruncatable = Real(8388608);  // 2^23
  if (!(std::fabs(x) < kTruncatable)) return std::floor(x);
  if (x == 0) return x;
  const Real t = static_cast<Real>(static_cast<long long>(x));
  return t > x ? t - 1 : t;
}

}  // namespace

void ModelBuilder::prepareVertexHash() {
  if (!brushes_.empty()) {
    clearHash(nodeBounds());
  } else {
    const Real b = tol::kDefaultHashBounds;
    clearHash(Bounds{{-b, -b, -b}, {b, b, b}});
  }
}

void ModelBuilder::clearHash(const Bounds& bounds, std::size_t expectedVertices) {
  hashMin_ = bounds.min;
  recent_.clear();
  vertexHashSize_ = kVertexHashSize;
  while (vertexHashSize_ < kMaxVertexHashSize && std::size_t(vertexHashSize_) < 2 * expectedVertices)
    vertexHashSize_ *= 2;
  vertexHashHead_.assign(std::size_t(vertexHashSize_), kNone);
  vertexHashNodes_.clear();
  edgeHashHead_.clear();
  edgeHashNext_.clear();
}

bool ModelBuilder::getVertex(const Vec3& v, int& vertexNum) {
  // The points of the last few lookups (a polygon's closing edge and a
  // two-sided polygon's back meet them again) and what they gave: a lookup's
  // answer depends only on the vertices that match its point, so it stays
  // the same until a new vertex matches it (findOrAddVertex drops such
  // entries).
  // (Entries with equal points hold the same vertex: any one that matches.)
  if (recentVertex(v, vertexNum)) return true;
  // Coordinates this close to an integer snap to it.
  Vec3 vert;
  for (int i = 0; i < 3; ++i) {
    const Real r = floorOf(v[i] + Real(0.5));
    vert[i] = std::fabs(v[i] - r) < tol::kIntegralEpsilon ? r : v[i];
  }
  const bool found = findOrAddVertex(vert, vertexNum);
  RecentVertices& r = recent_;
  const std::size_t k = r.next;
  r.x[k] = v.x;
  r.y[k] = v.y;
  r.z[k] = v.z;
  r.weldedX[k] = vert.x;
  r.weldedY[k] = vert.y;
  r.weldedZ[k] = vert.z;
  r.vertexNum[k] = vertexNum;
  r.valid |= 1u << k;
  r.next = (k + 1) % RecentVertices::kRecent;
  return found;
}

bool ModelBuilder::recentVertex(const Vec3& v, int& vertexNum) const {
  const RecentVertices& r = recent_;
  unsigned hits = 0;
#ifdef CMKIT_FLOAT_LANES
  static_assert(RecentVertices::kRecent % 4 == 0);
  const simd::F4 px = simd::F4::all(v.x), py = simd::F4::all(v.y), pz = simd::F4::all(v.z);
  for (std::size_t k = 0; k < RecentVertices::kRecent; k += 4) {
    const simd::F4 same =
        (simd::F4::load(&r.x[k]) == px) & (simd::F4::load(&r.y[k]) == py) & (simd::F4::load(&r.z[k]) == pz);
    hits |= simd::bits(same) << k;
  }
#else
  for (std::size_t k = 0; k < RecentVertices::kRecent; ++k)
    hits |= (unsigned(r.x[k] == v.x) & unsigned(r.y[k] == v.y) & unsigned(r.z[k] == v.z)) << k;
#endif
  hits &= r.valid;
  if (hits == 0) return false;
  vertexNum = r.vertexNum[std::size_t(std::countr_zero(hits))];
  return true;
}

bool ModelBuilder::findOrAddVertex(const Vec3& vert, int& vertexNum) {
  const double lo = tol::kVertexHashOffset - tol::kVertexHashSpread;
  const double hi = tol::kVertexHashOffset + tol::kVertexHashSpread;
  int kMid[3];
  for (int a = 0; a < 3; ++a) kMid[a] = axisCell(vert[a], hashMin_[a], tol::kVertexHashOffset);
  auto matches = [&](int vn) {
    const Vec3& p = hashNode(vn).position;
    return std::fabs(vert[2] - p[2]) < tol::kVertexEpsilon &&
           std::fabs(vert[0] - p[0]) < tol::kVertexEpsilon && std::fabs(vert[1] - p[1]) < tol::kVertexEpsilon;
  };
  // Newest first within a cell, as the original's hash chains.
  auto searchCell = [&](int key) {
    for (int vn = hashHead(key); vn != kNone; vn = hashNode(vn).next) {
      if (matches(vn)) return vn;
    }
    return kNone;
  };
  const int midKey = combineCells(kMid, vertexHashSize_);
  int found = searchCell(midKey);
  // The cells a weld reaches across, only when the vertex's own has no match.
  int kLo[3] = {};
  int kHi[3] = {};
  int differing = 0;
  if (found == kNone) {
    for (int a = 0; a < 3; ++a) {
      kLo[a] = axisCell(vert[a], hashMin_[a], lo);
      kHi[a] = axisCell(vert[a], hashMin_[a], hi);
      if (kLo[a] != kHi[a]) ++differing;
    }
  }
  if (found == kNone && differing == 1) {
    int other[3];
    for (int a = 0; a < 3; ++a) other[a] = kMid[a] == kLo[a] ? kHi[a] : kLo[a];
    found = searchCell(combineCells(other, vertexHashSize_));
  } else if (found == kNone && differing > 1) {
    // The original searches all vertices in order here; any vertex within
    // the weld distance lies in one of these cells, so the lowest-numbered
    // match among them is the same vertex, found without a linear scan.
    int keys[8];
    int numKeys = 0;
    for (int c = 0; c < 8; ++c) {
      int k[3];
      for (int a = 0; a < 3; ++a) k[a] = (c >> a) & 1 ? kHi[a] : kLo[a];
      const int key = combineCells(k, vertexHashSize_);
      bool seen = false;
      for (int s = 0; s < numKeys; ++s) seen = seen || keys[s] == key;
      if (!seen) keys[numKeys++] = key;
    }
    for (int s = 0; s < numKeys; ++s) {
      for (int vn = hashHead(keys[s]); vn != kNone; vn = hashNode(vn).next) {
        if ((found == kNone || vn < found) && matches(vn)) found = vn;
      }
    }
  }
  if (found != kNone) {
    vertexNum = found;
    return true;
  }
  vertexNum = static_cast<int>(vertices_.size());
  vertices_.push_back(vert);
  vertexHashNodes_.push_back({vert, hashHead(midKey)});
  hashHead(midKey) = vertexNum;
  // Recent lookups whose point the new vertex matches may now give it.
  RecentVertices& r = recent_;
  for (std::size_t k = 0; k < RecentVertices::kRecent; ++k) {
    const unsigned matches = unsigned(std::fabs(r.weldedZ[k] - vert[2]) < tol::kVertexEpsilon) &
                             unsigned(std::fabs(r.weldedX[k] - vert[0]) < tol::kVertexEpsilon) &
                             unsigned(std::fabs(r.weldedY[k] - vert[1]) < tol::kVertexEpsilon);
    r.valid &= ~(matches << k);
  }
  return false;
}

bool ModelBuilder::getEdge(const Vec3& v1, const Vec3& v2, int& edgeNum, int v1num) {
  if (edges_.empty()) {
    edges_.emplace_back();  // the dummy edge 0
    edgeHashNext_.push_back(kNone);
  }
  bool found = v1num != kNone ? true : getVertex(v1, v1num);
  int v2num = kNone;
  found = getVertex(v2, v2num) && found;
  if (v1num == v2num) {  // degenerate: both ends welded together
    edgeNum = 0;
    return true;
  }
  if (found) {
    // Share an edge only with one polygon that uses it the other way.
    for (int e = edgeHashHead_.find(edgeKey(v2num, v1num)); e != kNone;
         e = edgeHashNext_[static_cast<std::size_t>(e)]) {
      if (edge(e).numUsers != 1) continue;
      edge(e).numUsers++;
      edgeNum = -e;
      return true;
    }
  }
  edgeNum = addEdge(v1num, v2num);
  return false;
}

int ModelBuilder::addEdge(int v1num, int v2num) {
  BEdge newEdge;
  newEdge.v[0] = v1num;
  newEdge.v[1] = v2num;
  newEdge.numUsers = 1;
  const int e = static_cast<int>(edges_.size());
  edges_.push_back(newEdge);
  int& head = edgeHashHead_.at(edgeKey(v1num, v2num));
  edgeHashNext_.push_back(head);  // kNone (IntHashMap::kEmpty) for the first
  head = e;
  return e;
}

void ModelBuilder::createPolygon(const Winding& w, const Plane& plane, int material, int primitiveNum) {
  EdgeList polyEdges;
  polyEdges.reserve(static_cast<std::size_t>(w.size()));
  int v1num = kNone;  // the welded start of the next edge, once known
  for (int i = 0, j = 1; i < w.size(); ++i, ++j) {
    if (j >= w.size()) j = 0;
    int e = 0;
    getEdge(w[i], w[j], e, v1num);
    if (e != 0) {
      v1num = edge(e).v[e > 0 ? 1 : 0];  // the end of this edge starts the next
      polyEdges.push_back(e);
    }
  }
  if (polyEdges.size() < 3) return;
  for (std::size_t i = 0; i < polyEdges.size(); ++i) {
    for (std::size_t j = i + 1; j < polyEdges.size(); ++j) {
      if (std::abs(polyEdges[i]) == std::abs(polyEdges[j])) return;  // an edge used twice
    }
  }
  if (!edgesFormLoop(polyEdges)) {
    // Welding met non-finite or enormous coordinates (found by fuzzing; real
    // maps never get here): the original would keep an outline that is not
    // closed, which no query can use correctly.
    warn("primitive " + std::to_string(std::abs(primitiveNum)) +
         " is degenerate: a polygon's welded edges do not form a loop; dropped");
    return;
  }
  if (polyEdges.size() > static_cast<std::size_t>(tol::kMaxPolygonEdges)) {
    warn("polygon has " + std::to_string(polyEdges.size()) + " edges; truncated to " +
         std::to_string(tol::kMaxPolygonEdges));
    polyEdges.truncate(static_cast<std::size_t>(tol::kMaxPolygonEdges));
  }
  addPolygon(std::move(polyEdges), materials_[material].info.contents, material, plane, w.bounds());
}

void ModelBuilder::addPolygon(EdgeList&& edges, std::uint32_t contents, int material, const Plane& plane,
                              const Bounds& bounds) {
  BPolygon p;
  p.edges = std::move(edges);
  p.contents = contents;
  p.material = material;
  p.plane = plane;
  p.bounds = bounds;
  polygons_.push_back(std::move(p));
  filterIntoTree(ItemKind::Polygon, 0, static_cast<int>(polygons_.size()) - 1);
}

void ModelBuilder::polygonFromWinding(Winding& w, const Plane& plane, int material, int primitiveNum) {
  const MaterialInfo& info = materials_[material].info;
  if (choppedAwayByProcBsp(w, plane, info.contents)) {
    counters_.numRemovedPolys++;  // in solid leaves of the .proc BSP (world model only)
    counters_.numProcRemovedPolys++;
    return;
  }
  const Winding* out = windingOutsideBrushes(w, plane, info.contents, primitiveNum);
  if (!out) {
    counters_.numRemovedPolys++;  // fully inside brushes
    return;
  }
  if (out->isHuge()) {
    warn("primitive " + std::to_string(std::abs(primitiveNum)) +
         " is degenerate: a polygon reaches the world limit; dropped");
    return;
  }
  const std::size_t made = polygons_.size();
  createPolygon(*out, plane, material, primitiveNum);
  if (info.twoSided && !createReversedCopy(*out, plane, made)) {
    reversed_ = *out;  // (keeps the room of the last one)
    reversed_.reverse();
    createPolygon(reversed_, plane.flipped(), material, primitiveNum);
  }
}

bool ModelBuilder::createReversedCopy(const Winding& w, const Plane& plane, std::size_t original) {
  // What createPolygon of w reversed would do, worked out from the original
  // polygon instead of the welding and edge hashes: when the original was
  // made with one new edge per point of w (none dropped or truncated), each
  // point's lookup still gives the vertex that the original's edge from it
  // starts at (a recent lookup that holds: no new vertex matched it since),
  // and each of those edges is still the newest of its direction with its one
  // user, the reversed copy's getEdge finds each of them in turn and shares
  // it: reversing w = p0..p(n-1) gives the edges -e(n-2), ..., -e0, -e(n-1)
  // of the original's e0..e(n-1) (e(k) from p(k)). The rest of createPolygon
  // (distinct edges, a closed loop) holds as it did for the original.
  if (polygons_.size() != original + 1) return false;
  const EdgeList& edges = polygons_[original].edges;
  const std::size_t n = edges.size();
  if (n != static_cast<std::size_t>(w.size())) return false;
  for (std::size_t k = 0; k < n; ++k) {
    const int e = edges[k];
    if (e <= 0) return false;  // (shared with an earlier polygon)
    const BEdge& be = edge(e);
    int vertexNum = kNone;
    if (be.numUsers != 1 || !recentVertex(w[static_cast<int>(k)], vertexNum) || vertexNum != be.v[0] ||
        edgeHashHead_.find(edgeKey(be.v[0], be.v[1])) != e)
      return false;
  }
  EdgeList reversedEdges;
  reversedEdges.reserve(n);
  for (std::size_t k = n - 1; k-- > 0;) reversedEdges.push_back(-edges[k]);
  reversedEdges.push_back(-edges[n - 1]);
  for (std::size_t k = 0; k < n; ++k) edge(edges[k]).numUsers++;
  Bounds bounds;
  for (int k = w.size(); k-- > 0;) bounds.addPoint(w[k]);  // (in the reversed winding's order)
  const BPolygon& o = polygons_[original];
  addPolygon(std::move(reversedEdges), o.contents, o.material, plane.flipped(), bounds);
  return true;
}

}  // namespace cmkit::detail
