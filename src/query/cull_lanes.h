// Internal: a model's cull blocks (model/query_data.h) culled four polygons
// at a time in SSE2 lanes, each lane doing the arithmetic of the scalar
// culls (trace_work.h: boxesTouch, boxBeyondPlane) operation for operation,
// so the same answers. Used by the translation and rotation walks of models
// with query data; only where CMKIT_QUERY_LANES is defined.
#pragma once

#include <bit>

#include "model/query_data.h"
#include "query/trace_work.h"

#ifdef CMKIT_QUERY_LANES
#include <emmintrin.h>

namespace cmkit::detail {

/// The centres and half sizes of a cull block's four boxes (boxPlaneSpan's).
inline void blockBoxes(const CullBlock& b, __m128 centre[3], __m128 reach[3]) {
  const __m128 half = _mm_set1_ps(Real(0.5));
  for (int k = 0; k < 3; ++k) {
    const __m128 min = _mm_load_ps(b.min[k]), max = _mm_load_ps(b.max[k]);
    centre[k] = _mm_mul_ps(_mm_add_ps(min, max), half);
    reach[k] = _mm_sub_ps(max, centre[k]);
  }
}

/// boxBeyondPlane in four lanes (boxes given by their centres and half sizes).
inline __m128 boxesBeyondPlane(const __m128 centre[3], const __m128 reach[3], const Plane& plane,
                               Real maxDist) {
  const __m128 absMask = _mm_castsi128_ps(_mm_set1_epi32(0x7fffffff));
  const __m128 signMask = _mm_castsi128_ps(_mm_set1_epi32(int(0x80000000u)));
  const __m128 nx = _mm_set1_ps(plane.normal.x), ny = _mm_set1_ps(plane.normal.y);
  const __m128 nz = _mm_set1_ps(plane.normal.z);
  const __m128 d1 = _mm_sub_ps(
      _mm_add_ps(_mm_add_ps(_mm_mul_ps(nx, centre[0]), _mm_mul_ps(ny, centre[1])), _mm_mul_ps(nz, centre[2])),
      _mm_set1_ps(plane.dist));
  const __m128 d2 = _mm_add_ps(_mm_add_ps(_mm_and_ps(_mm_mul_ps(reach[0], nx), absMask),
                                          _mm_and_ps(_mm_mul_ps(reach[1], ny), absMask)),
                               _mm_and_ps(_mm_mul_ps(reach[2], nz), absMask));
  const __m128 limit = _mm_set1_ps(maxDist);
  return _mm_or_ps(_mm_cmpgt_ps(_mm_sub_ps(d1, d2), limit),
                   _mm_cmpgt_ps(_mm_xor_ps(_mm_add_ps(d1, d2), signMask), limit));
}

/// The trace bounds and the content mask, broadcast to four lanes once (and
/// again, by load, when a hit shrinks the bounds).
struct BoundsLanes {
  __m128 min[3], max[3];
  __m128i contentMask;
  explicit BoundsLanes(const TraceWork& tw) { load(tw); }
  void load(const TraceWork& tw) {
    for (int k = 0; k < 3; ++k) {
      min[k] = _mm_set1_ps(tw.bounds.min[k]);
      max[k] = _mm_set1_ps(tw.bounds.max[k]);
    }
    contentMask = _mm_set1_epi32(int(tw.contentMask));
  }
  /// Lanes whose polygon shares a content flag and whose bounds touch the
  /// trace bounds (bit j for lane j).
  unsigned pass(const CullBlock& b) const {
    const __m128i contents = _mm_load_si128(reinterpret_cast<const __m128i*>(b.contents));
    __m128 culled =
        _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(contents, contentMask), _mm_setzero_si128()));
    for (int k = 0; k < 3; ++k) {  // boxesTouch(tw.bounds, polygon bounds)
      culled = _mm_or_ps(culled, _mm_cmplt_ps(_mm_load_ps(b.max[k]), min[k]));
      culled = _mm_or_ps(culled, _mm_cmpgt_ps(_mm_load_ps(b.min[k]), max[k]));
    }
    return ~unsigned(_mm_movemask_ps(culled)) & 0xFu;
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
template <class F>
bool forEachBlockPassing(std::uint64_t mask, F f) {
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

}  // namespace cmkit::detail

#endif  // CMKIT_QUERY_LANES
