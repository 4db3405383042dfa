// Internal: a model's cull blocks (model/query_data.h) culled four polygons
// at a time in SSE2 lanes, each lane doing the arithmetic of the scalar
// culls (trace_work.h: boxesTouch, boxBeyondPlane) operation for operation,
// so the same answers. Used by the translation and rotation walks of models
// with query data; only where CMKIT_QUERY_LANES is defined (util/simd.h's
// float lanes).
#pragma once

#include <bit>

#include "model/query_data.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES
#include "util/simd.h"

namespace cmkit::detail {

using simd::F4;
using simd::U4;

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
