// Internal: a model's cull blocks (model/query_data.h) culled four polygons
// at a time in SSE2 lanes, each lane doing the arithmetic of the scalar
// culls (trace_work.h: boxesTouch, boxBeyondPlane) operation for operation,
// so the same answers. Used by the translation and rotation walks of models
// with query data. Also the trace model four vertices or polygons at a time:
// placed when turned (placement.cpp, translate_setup.cpp) and read back as
// rows (translate.cpp), with the scalar placement's arithmetic in each lane.
// Only where CMKIT_QUERY_LANES is defined (util/simd.h's float lanes).
#pragma once

#include <bit>

#include "model/query_data.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES
#include "util/simd.h"

namespace cmkit::detail {

using simd::F4;
using simd::U4;

/// Rows x, y, z of four vectors (lane j vector j).
inline void vectorRows(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d, F4& x, F4& y, F4& z) {
  x = F4::lanes(a.x, b.x, c.x, d.x);
  y = F4::lanes(a.y, b.y, c.y, d.y);
  z = F4::lanes(a.z, b.z, c.z, d.z);
}
/// a * x + b * y + c * z in each lane, in that order (a row or column of a
/// matrix times a vector, as Mat3's scalar products make it).
inline F4 weightedSum(float a, float b, float c, F4 x, F4 y, F4 z) {
  return F4::all(a) * x + F4::all(b) * y + F4::all(c) * z;
}
/// Row vectors times m (Vec3 * Mat3's arithmetic in each lane: column k of
/// m weights x, y, z).
inline void timesMat3(const Mat3& m, F4& x, F4& y, F4& z) {
  const Vec3 &r0 = m.rows[0], &r1 = m.rows[1], &r2 = m.rows[2];
  const F4 ox = weightedSum(r0.x, r1.x, r2.x, x, y, z);
  const F4 oy = weightedSum(r0.y, r1.y, r2.y, x, y, z);
  z = weightedSum(r0.z, r1.z, r2.z, x, y, z);
  x = ox;
  y = oy;
}
/// m times column vectors (Mat3 * Vec3's arithmetic in each lane: row k of
/// m weights x, y, z).
inline void mat3Times(const Mat3& m, F4& x, F4& y, F4& z) {
  const auto row = [&](int k) { return weightedSum(m.rows[k].x, m.rows[k].y, m.rows[k].z, x, y, z); };
  const F4 ox = row(0), oy = row(1);
  z = row(2);
  x = ox;
  y = oy;
}

/// Trace-model vertices 0 .. numVerts - 1 in the model's frame, the trace
/// model at `relative` (as placedTrmVertex), four at a time with its
/// arithmetic in each lane (the same bits), into x, y, z (arrays of
/// kMaxTrmVertices; the entries up to the next multiple of four written too).
inline void placedTrmVerticesInLanes(const TraceModel& trm, const Orientation& o, const Vec3& relative,
                                     int numVerts, float* px, float* py, float* pz) {
  static_assert(kMaxTrmVertices % 4 == 0);
  for (int k = 0; 4 * k < numVerts; ++k) {
    F4 x, y, z;
    vectorRows(trm.vertex(4 * k), trm.vertex(4 * k + 1), trm.vertex(4 * k + 2), trm.vertex(4 * k + 3), x, y,
               z);
    if (o.trmRotated) timesMat3(*o.trmAxis, x, y, z);
    x = x + F4::all(relative.x);
    y = y + F4::all(relative.y);
    z = z + F4::all(relative.z);
    if (o.modelRotated) mat3Times(o.placement->axis, x, y, z);
    x.store(px + 4 * k);
    y.store(py + 4 * k);
    z.store(pz + 4 * k);
  }
}

/// Trace-model polygons 0 .. numPolys - 1's normals in the model's frame for
/// a turned trace model or placement (planeAxis: trmPlaneAxis's), as
/// placeTrmPolygon turns them, four at a time with its arithmetic in each
/// lane (the same bits), into x, y, z (arrays of kMaxTrmPolygons; the
/// entries up to the next multiple of four written too, from the unused
/// zero normals).
inline void turnedTrmNormalsInLanes(const TraceModel& trm, const Orientation& o, const Mat3& planeAxis,
                                    int numPolys, float* nx, float* ny, float* nz) {
  static_assert(kMaxTrmPolygons % 4 == 0);
  for (int k = 0; 4 * k < numPolys; ++k) {
    F4 x, y, z;
    vectorRows(trm.polygonNormal(4 * k), trm.polygonNormal(4 * k + 1), trm.polygonNormal(4 * k + 2),
               trm.polygonNormal(4 * k + 3), x, y, z);
    if (o.trmRotated)
      timesMat3(planeAxis, x, y, z);
    else
      mat3Times(o.placement->axis, x, y, z);
    x.store(nx + 4 * k);
    y.store(ny + 4 * k);
    z.store(nz + 4 * k);
  }
}

/// placeTrmPolygon for every polygon of a turned trace model or placement,
/// the normals four at a time (turnedTrmNormalsInLanes, also left in nx, ny,
/// nz).
inline void placeTurnedTrmPolygons(TraceWork& tw, const TraceModel& trm, const Orientation& o,
                                   const Mat3& planeAxis, float* nx, float* ny, float* nz) {
  turnedTrmNormalsInLanes(trm, o, planeAxis, tw.numPolys, nx, ny, nz);
  for (int i = 0; i < tw.numPolys; ++i) {
    WorkPolygon& wp = tw.polys[std::size_t(i)];
    wp.source = &trm.polygon(i);
    wp.planeVertex = trm.polygonPlaneVertex(i);
    wp.plane.normal = {nx[i], ny[i], nz[i]};
  }
}

/// The start positions of trace-model vertices 4k .. 4k + 3 as rows: x, y, z
/// (lane j vertex 4k + j). Entries past the trace model's vertices are
/// stale (the caller masks their lanes); k < kMaxTrmVertices / 4.
inline void trmVertexRows(const TraceWork& tw, int k, F4& x, F4& y, F4& z) {
  // (Each load reads p and the first float of endp: a vertex's record is
  // longer than 16 bytes, so none reads past the array.)
  x = F4::loadUnaligned(&tw.vertices[std::size_t(4 * k)].p.x);
  y = F4::loadUnaligned(&tw.vertices[std::size_t(4 * k + 1)].p.x);
  z = F4::loadUnaligned(&tw.vertices[std::size_t(4 * k + 2)].p.x);
  F4 w = F4::loadUnaligned(&tw.vertices[std::size_t(4 * k + 3)].p.x);
  simd::transpose(x, y, z, w);
}

/// The lanes of block k of the trace model's vertices (lane j vertex 4k + j)
/// whose bit is not set in `vertices`: all bits set there.
inline F4 trmVertexLanesOutside(std::uint32_t vertices, int k) {
  alignas(16) static constexpr std::uint32_t kLaneBits[kLanes] = {1, 2, 4, 8};
  return simd::noCommonBits(U4::all(vertices >> (4 * k)), U4::load(kLaneBits));
}

/// The centres and half sizes of a cull block's four boxes (boxPlaneSpan's).
inline void blockBoxes(const CullBlock& b, F4 centre[3], F4 reach[3]) {
  const F4 half = F4::all(Real(0.5));
  for (int k = 0; k < 3; ++k) {
    const F4 min = F4::load(b.min[k]), max = F4::load(b.max[k]);
    centre[k] = (min + max) * half;
    reach[k] = max - centre[k];
  }
}

/// boxBeyondPlane in four lanes (boxes given by their centres and half sizes).
inline F4 boxesBeyondPlane(const F4 centre[3], const F4 reach[3], const Plane& plane, Real maxDist) {
  const F4 nx = F4::all(plane.normal.x), ny = F4::all(plane.normal.y), nz = F4::all(plane.normal.z);
  const F4 d1 = nx * centre[0] + ny * centre[1] + nz * centre[2] - F4::all(plane.dist);
  const F4 d2 = simd::abs(reach[0] * nx) + simd::abs(reach[1] * ny) + simd::abs(reach[2] * nz);
  const F4 limit = F4::all(maxDist);
  return (d1 - d2 > limit) | (simd::negate(d1 + d2) > limit);
}

/// The trace bounds and the content mask, broadcast to four lanes once (and
/// again, by load, when a hit shrinks the bounds).
struct BoundsLanes {
  F4 min[3], max[3];
  U4 contentMask;
  explicit BoundsLanes(const TraceWork& tw) { load(tw); }
  void load(const TraceWork& tw) {
    for (int k = 0; k < 3; ++k) {
      min[k] = F4::all(tw.bounds.min[k]);
      max[k] = F4::all(tw.bounds.max[k]);
    }
    contentMask = U4::all(tw.contentMask);
  }
  /// Lanes whose polygon shares a content flag and whose bounds touch the
  /// trace bounds (bit j for lane j).
  unsigned pass(const CullBlock& b) const {
    F4 culled = simd::noCommonBits(U4::load(b.contents), contentMask);
    for (int k = 0; k < 3; ++k) {  // boxesTouch(tw.bounds, polygon bounds)
      culled = culled | (F4::load(b.max[k]) < min[k]);
      culled = culled | (F4::load(b.min[k]) > max[k]);
    }
    return ~simd::bits(culled) & 0xFu;
  }
};

/// Blocks culled together by chunkPass: one bit per lane of a 64-bit mask.
inline constexpr std::size_t kChunkBlocks = 64 / kLanes;

/// The lanes of the blocks from `chunk` (up to kChunkBlocks of them, before
/// endBlock) that pass BoundsLanes::pass, as one mask (block k's lanes at
/// bits kLanes * k ..), keeping only the entries first .. end - 1 (a node's:
/// the first and last block may hold other nodes' entries). Without a branch
/// per block: which pass is unpredictable.
inline std::uint64_t chunkPass(const BoundsLanes& bounds, const CullBlock* blocks, std::size_t chunk,
                               std::size_t endBlock, std::size_t first, std::size_t end) {
  const std::size_t numBlocks = std::min(kChunkBlocks, endBlock - chunk);
  std::uint64_t mask = 0;
  for (std::size_t k = 0; k < numBlocks; ++k)
    mask |= std::uint64_t(bounds.pass(blocks[chunk + k])) << (kLanes * k);
  const std::size_t base = chunk * kLanes;
  const std::size_t lo = first > base ? first - base : 0, hi = std::min(end - base, std::size_t(64));
  return mask & (hi == 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << hi) - 1) &
         ~((std::uint64_t(1) << lo) - 1);
}

/// Calls f(k, pass) for each block k of a chunk (k = 0 .. kChunkBlocks - 1)
/// with a lane left in `mask` (chunkPass's), in order, `pass` its lanes (bit
/// j for lane j); stops when f returns true, and returns whether it did.
/// Always inline, into the walk of each kind: GCC left the rotations' copy
/// out of line (with its lambda, a call per chunk of blocks).
template <class F>
[[gnu::always_inline]] inline bool forEachBlockPassing(std::uint64_t mask, F f) {
  while (mask) {
    const std::size_t k = std::size_t(std::countr_zero(mask)) / kLanes;
    const unsigned pass = unsigned(mask >> (kLanes * k)) & 0xFu;
    mask &= ~(std::uint64_t(0xF) << (kLanes * k));
    if (f(k, pass)) return true;
  }
  return false;
}

/// Counts a node's polygons met for the first time in the query (their own
/// marks: the walks over cull blocks mark only the polygons past the culls)
/// in a CMKIT_QUERY_STATS build; nothing otherwise.
inline void countPolygonsMet(TraceWork& tw, const CmNode& node) {
  if constexpr (kQueryStats) {
    QueryScratch& s = tw.scratch;
    for (const std::int32_t polyNum : tw.model.polygonsAt(node))
      if (!s.testAndMark(s.polygonMet, std::size_t(polyNum))) count(s, &QueryStats::polygonsMet);
  }
}

/// The walk of a node's polygons through its cull blocks, shared by the
/// translation and rotation walks: the contents and bounds of up to
/// kChunkBlocks blocks at a time (chunkPass), then, block by block in order,
/// the kind's own culls of the lanes left (Kind::blockPass(tw, block): the
/// lanes that pass), then Kind::test(tw, polyNum, polygon) for each lane left
/// whose polygon this query has not checked yet, in order; stops, returning
/// true, when a test does (the trace model is blocked completely). With
/// Kind::kShrinks (a translation: a hit shrinks the trace bounds) the lanes
/// left and the blocks after a hit are culled again with the new bounds.
template <class Kind>
bool walkCullBlocks(TraceWork& tw, const QueryData& d, const CmNode& node) {
  QueryScratch& s = tw.scratch;
  const std::size_t first = node.firstPolygonRef, end = first + node.numPolygonRefs;
  CMKIT_ASSERT(end <= tw.model.polygonRefs().size() && d.culls.size() * kLanes >= end);
  countPolygonsMet(tw, node);
  BoundsLanes bounds(tw);
  const std::size_t firstBlock = first / kLanes, endBlock = (end + kLanes - 1) / kLanes;
  for (std::size_t chunk = firstBlock; chunk < endBlock; chunk += kChunkBlocks) {
    const Real maskFraction = tw.fraction;
    const bool blocked = forEachBlockPassing(
        chunkPass(bounds, d.culls.data(), chunk, endBlock, first, end), [&](std::size_t k, unsigned pass) {
          const CullBlock& b = d.culls[chunk + k];
          if constexpr (Kind::kShrinks) {
            if (tw.fraction != maskFraction && (pass &= bounds.pass(b)) == 0) return false;
          }
          pass &= Kind::blockPass(tw, b);
          const std::size_t entry = (chunk + k) * kLanes;
          while (pass) {
            const std::int32_t polyNum = tw.model.polygonRefs()[entry + std::size_t(std::countr_zero(pass))];
            pass &= pass - 1;
            if (s.testAndMark(s.polygonChecked, std::size_t(polyNum))) continue;
            [[maybe_unused]] const Real before = tw.fraction;
            if (Kind::test(tw, polyNum, tw.model.polygons()[std::size_t(polyNum)])) return true;
            if constexpr (Kind::kShrinks) {
              if (tw.fraction != before) {  // the bounds may have shrunk
                bounds.load(tw);
                pass &= bounds.pass(b);
              }
            }
          }
          return false;
        });
    if (blocked) return true;
  }
  return false;
}

}  // namespace cmkit::detail

#endif  // CMKIT_QUERY_LANES
