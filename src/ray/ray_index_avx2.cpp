// The AVX2 node test of RayIndex: all eight children of a node in one pass
// (castAvx2), and the packet walk of RayIndex::castMany: eight rays against
// one child in one pass (castPacketAvx2). This file is compiled with -mavx2
// -mfma (src/CMakeLists.txt) and only called when the processor has both
// (RayIndex picks it when built); everything it runs is here or in
// ray_index_kernel.h, which explains the rules this file keeps: no inline
// functions of other headers, only intrinsics, builtins and its own
// internal-linkage code.
#include "ray/ray_index_kernel.h"

#if defined(CMKIT_AVX2_KERNEL) && !defined(CMKIT_NO_SIMD)
#include <immintrin.h>
#endif

namespace cmkit::detail {

#if defined(CMKIT_AVX2_KERNEL) && !defined(CMKIT_NO_SIMD)
namespace {

/// As enteredChildren in ray_index.cpp on all eight children at once, where
/// the ray meets a plane x = row by one fused multiply-add, row * inv -
/// start * inv (PacketRays below says why the answers are the same).
__attribute__((always_inline)) inline int enteredChildrenAvx2(const RayLayout::Node& n, const Ray& r,
                                                              float best, float* entry) {
  const auto* base = reinterpret_cast<const char*>(&n);
  const auto row = [base](std::size_t offset) {
    return _mm256_load_ps(reinterpret_cast<const float*>(base + offset));
  };
  const auto along = [&](int axis, const std::size_t* rows) {
    return _mm256_fmsub_ps(row(rows[axis]), _mm256_set1_ps(r.inv[axis]),
                           _mm256_set1_ps(r.startTimesInv[axis]));
  };
  const __m256 tNear = _mm256_max_ps(_mm256_max_ps(along(1, r.nearRow), along(0, r.nearRow)),
                                     _mm256_max_ps(along(2, r.nearRow), _mm256_setzero_ps()));
  const __m256 tFar = _mm256_min_ps(_mm256_min_ps(along(1, r.farRow), along(0, r.farRow)),
                                    _mm256_min_ps(along(2, r.farRow), _mm256_set1_ps(best)));
  const __m256i noContents =
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_load_si256(reinterpret_cast<const __m256i*>(n.contents)),
                                          _mm256_set1_epi32(int(r.mask))),
                         _mm256_setzero_si256());
  _mm256_store_ps(entry, tNear);
  return _mm256_movemask_ps(
      _mm256_andnot_ps(_mm256_castsi256_ps(noContents), _mm256_cmp_ps(tNear, tFar, _CMP_LE_OQ)));
}

/// One field of the packet's rays as the eight float lanes of a register
/// (lanes past `count` repeat ray 0, and stay off). Built in registers, not
/// through an array on the stack: eight scalar stores read back as one
/// vector miss the store forwarding and wait for the stores to retire, which
/// showed in profiles as a large share of a packet's walk.
template <class Field>
__m256 packetLanes(const Ray* rays, unsigned count, Field field) {
  const auto lane = [&](unsigned k) { return float(field(rays[k < count ? k : 0])); };
  return _mm256_setr_ps(lane(0), lane(1), lane(2), lane(3), lane(4), lane(5), lane(6), lane(7));
}

/// A child waiting on a packet's stack: the rays (lane bits) that enter
/// it and where each enters (+infinity in the other lanes).
struct PacketPending {
  __m256 t;
  std::uint32_t ref;
  std::uint32_t lanes;
};

/// The packet's rays for the slab test of a child box: where a ray meets
/// the plane x = row is row * inv - start * inv (one fused multiply-add per
/// plane, as in enteredChildrenAvx2), the near face the smaller of the two
/// slab distances. This rounds differently from the baseline node test's
/// (row - start) * inv (enteredChildren in ray_index.cpp), so one may enter
/// a box the other skips, only within the rounding of the slab test, which
/// the node boxes' padding covers (tol::kRayNodePadding): every box still
/// contains every crossing its polygons accept, so each ray's answer is the
/// same.
struct PacketRays {
  __m256 startTimesInv[3];
  __m256 inv[3];
};

/// The plane part of a polygon's test (crossesPlanes, ray_index_kernel.h)
/// for the eight rays of a packet at once:
/// which rays may cross the polygon (or with `twin` the lane's twin) before
/// their best crossing (front face, start not behind, end not in front,
/// crossing not beyond the best) and where (t), by the same float
/// operations in the same order as crossesPlanes, so the rays it passes go
/// on with the t crossesPlanes would compute; and the edge tests of several
/// rays at once. A double build (Real is double) does not filter: every ray
/// goes to crossesPlanes.
class PacketPlanes {
 public:
  /// Whether Real is float, so that the lanes compute what crossesPlanes does.
  static constexpr bool kFloatLanes = sizeof(Real) == sizeof(float);

  PacketPlanes(const Ray* rays, unsigned count) {
    if constexpr (kFloatLanes) {
      for (int a = 0; a < 3; ++a) {
        start_[a] = packetLanes(rays, count, [a](const Ray& r) { return r.start[a]; });
        end_[a] = packetLanes(rays, count, [a](const Ray& r) { return r.end[a]; });
        dir_[a] = packetLanes(rays, count, [a](const Ray& r) { return r.dir[a]; });
      }
      for (int c = 0; c < 6; ++c)
        line_[c] = packetLanes(rays, count, [c](const Ray& r) { return r.line[c]; });
    }
  }
  /// Of the rays in `lanes`, those that may cross lane k's polygon (with
  /// `twin`: its twin, every sign of the test reversed) before their best
  /// (bestT), with where in tOut (written only when some ray may).
  std::uint32_t candidates(const RayLayout::LeafHead& h, std::uint32_t k, bool twin, const float* bestT,
                           std::uint32_t lanes, float* tOut) const {
    if constexpr (!kFloatLanes) {
      return lanes;
    } else {
      const __m256 nx = _mm256_set1_ps(float(h.x[k])), ny = _mm256_set1_ps(float(h.y[k]));
      const __m256 nz = _mm256_set1_ps(float(h.z[k])), dist = _mm256_set1_ps(float(h.dist[k]));
      const auto dot = [&](const __m256* v) {
        return _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(nx, v[0]), _mm256_mul_ps(ny, v[1])),
                             _mm256_mul_ps(nz, v[2]));
      };
      const __m256 zero = _mm256_setzero_ps();
      const __m256 facing = dot(dir_);
      const __m256 d1 = _mm256_sub_ps(dot(start_), dist);
      const __m256 d2 = _mm256_sub_ps(dot(end_), dist);
      const __m256 denom = _mm256_sub_ps(d1, d2);
      __m256 ok;
      if (!twin) {
        ok = _mm256_cmp_ps(facing, zero, _CMP_LT_OQ);                    // facing < 0
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(d1, zero, _CMP_NLT_UQ));    // !(d1 < 0)
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(d2, zero, _CMP_NGT_UQ));    // !(d2 > 0)
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(denom, zero, _CMP_GT_OQ));  // denom > 0
      } else {
        ok = _mm256_cmp_ps(facing, zero, _CMP_GT_OQ);                    // facing > 0
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(d1, zero, _CMP_NGT_UQ));    // !(d1 > 0)
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(d2, zero, _CMP_NLT_UQ));    // !(d2 < 0)
        ok = _mm256_and_ps(ok, _mm256_cmp_ps(denom, zero, _CMP_LT_OQ));  // denom < 0
      }
      // Most polygons of a leaf face away from every ray or are not reached:
      // the division only when some ray crosses the plane.
      if (!(std::uint32_t(_mm256_movemask_ps(ok)) & lanes)) return 0;
      const __m256 t = _mm256_div_ps(d1, denom);
      _mm256_store_ps(tOut, t);
      ok = _mm256_and_ps(ok, _mm256_cmp_ps(t, _mm256_load_ps(bestT), _CMP_NGT_UQ));  // !(t > best)
      return std::uint32_t(_mm256_movemask_ps(ok)) & lanes;
    }
  }
  /// Of the rays in `lanes`, those passing inside every edge of lane k's
  /// polygon (with `twin`: of its twin, outside every edge of the lane's
  /// polygon): insideEdges for eight rays at once. The products are
  /// cornerLine's (the same in every lane, so no pick of the edge's first
  /// vertex), whose sign bits say "outside" whether or not the polygon uses
  /// the edge reversed, except where one is zero: then edgeLine's, the
  /// model's line, as insideEdges computes it. Float lanes only
  /// (kFloatLanes).
  std::uint32_t insideEdges(const RayLayout::LeafHead& h, std::uint32_t k, bool twin,
                            std::uint32_t lanes) const {
    for (std::uint32_t j = 0; j < h.numEdges && lanes; ++j) {
      const EdgeCorners corners = edgeCorners(h, j);
      Real edge[6];
      cornerLine(corners, k, edge);
      __m256 product = productWith(edge);
      std::uint32_t outside = std::uint32_t(_mm256_movemask_ps(product));
      if (std::uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(product, _mm256_setzero_ps(), _CMP_EQ_OQ))) & lanes)
          [[unlikely]] {
        edgeLine(corners, k, edge);
        product = productWith(edge);
        outside = std::uint32_t(_mm256_movemask_ps(product)) ^ (std::uint32_t(0) - edgeReversed(corners, k));
      }
      // Inside a twin: outside the lane's polygon.
      lanes &= twin ? outside : ~outside;
    }
    return lanes;
  }

 private:
  /// edge . line_ for the eight rays, in edgeProduct's order.
  __m256 productWith(const Real* edge) const {
    const auto term = [&](int e, int r) { return _mm256_mul_ps(_mm256_set1_ps(float(edge[e])), line_[r]); };
    __m256 product = _mm256_add_ps(term(0, 4), term(1, 5));
    product = _mm256_add_ps(product, term(2, 3));
    product = _mm256_add_ps(product, term(4, 0));
    product = _mm256_add_ps(product, term(5, 1));
    return _mm256_add_ps(product, term(3, 2));
  }

  __m256 start_[3], end_[3], dir_[3];
  __m256 line_[6];  ///< the rays' Pluecker coordinates (Ray::line)
};

}  // namespace

Crossing castAvx2(const Arrays& index, const Ray& ray) {
  // (A lambda, not the function's address: the walk inlines the node test.)
  return walk(index, ray, [](const RayLayout::Node& n, const Ray& r, float best, float* entry) {
    return enteredChildrenAvx2(n, r, best, entry);
  });
}

void castPacketAvx2(const Arrays& index, const Ray* rays, unsigned count, Crossing* out) {
  constexpr int kWidth = RayLayout::kWidth;
  const std::uint32_t allLanes = (1u << count) - 1;
  const std::uint32_t mask = rays[0].mask;
  const PacketPlanes planes(rays, count);
  PacketRays pr;
  for (int a = 0; a < 3; ++a) {
    pr.inv[a] = packetLanes(rays, count, [a](const Ray& r) { return r.inv[a]; });
    pr.startTimesInv[a] = packetLanes(rays, count, [a](const Ray& r) { return r.startTimesInv[a]; });
  }
  Crossing best[kPacket];
  alignas(32) float bestT[kPacket];
  for (unsigned k = 0; k < kPacket; ++k) {
    best[k] = Crossing{1, -1, 0, 0, false};
    bestT[k] = 1.0f;
  }
  const __m256 infinity = _mm256_set1_ps(__builtin_huge_valf());
  const __m256i maskV = _mm256_set1_epi32(int(mask));
  // At most kWidth - 1 children wait per level, as in walk().
  PacketPending stack[(kWidth - 1) * kMaxDepth + kWidth];
  std::size_t sp = 0;
  std::uint32_t ref = 0;
  std::uint32_t lanes = allLanes;
  for (;;) {
    if (ref & RayLayout::kLeaf) {
      const RayLayout::LeafHead& h = leafHead(index, ref);
      const std::uint32_t count = leafCount(ref);
      // Each lane's polygon, then its twin if it has one.
      for (std::uint32_t side = 0; side < 2 * count; ++side) {
        const std::uint32_t i = side >> 1;
        const bool twin = (side & 1) != 0;
        if (!(h.contents[i] & mask) || (twin && !((h.twins >> i) & 1))) continue;
        const std::uint32_t rec = twin ? twinRecord(h, ref, i) : h.firstRecord + i;
        alignas(32) float t[kPacket];
        std::uint32_t l = planes.candidates(h, i, twin, bestT, lanes, t);
        if constexpr (PacketPlanes::kFloatLanes) {
          // Several rays: their edge tests at once; one: its own.
          const bool several = (l & (l - 1)) != 0;
          if (several) l = planes.insideEdges(h, i, twin, l);
          for (; l; l &= l - 1) {
            const int k = __builtin_ctz(l);
            if (notBeyondBest(index, rec, t[k], best[k]) && (several || insideEdges(h, i, rays[k], twin)))
              keepCrossing(index, ref, i, twin, rec, rays[k], t[k], best[k]);
            bestT[k] = float(best[k].t);
          }
        } else {
          for (; l; l &= l - 1) {
            const int k = __builtin_ctz(l);
            Real tk;
            bool front, back;
            crossesPlanes(h, i, rays[k], tk, front, back);
            if ((twin ? back : front) && notBeyondBest(index, rec, tk, best[k]) &&
                insideEdges(h, i, rays[k], twin))
              keepCrossing(index, ref, i, twin, rec, rays[k], tk, best[k]);
            bestT[k] = float(best[k].t);
          }
        }
      }
    } else {
      const RayLayout::Node& n = index.nodes[ref];
      const __m256 bestV = _mm256_load_ps(bestT);
      const __m256i noContents = _mm256_cmpeq_epi32(
          _mm256_and_si256(_mm256_load_si256(reinterpret_cast<const __m256i*>(n.contents)), maskV),
          _mm256_setzero_si256());
      std::uint32_t children = std::uint32_t(~_mm256_movemask_ps(_mm256_castsi256_ps(noContents))) & 0xffu;
      // The children some ray enters, nearest (smallest entry of any of its
      // rays) first: up to kWidth, insertion-sorted above the stack's top.
      PacketPending* order = stack + sp;
      float key[kWidth];
      std::size_t found = 0;
      for (; children; children &= children - 1) {
        const int c = __builtin_ctz(children);
        const auto slab = [&](int a, const float(*rows)[kWidth]) {
          return _mm256_fmsub_ps(_mm256_broadcast_ss(&rows[a][c]), pr.inv[a], pr.startTimesInv[a]);
        };
        const __m256 x0 = slab(0, n.min), x1 = slab(0, n.max);
        const __m256 y0 = slab(1, n.min), y1 = slab(1, n.max);
        const __m256 z0 = slab(2, n.min), z1 = slab(2, n.max);
        const __m256 tNear = _mm256_max_ps(_mm256_max_ps(_mm256_min_ps(y0, y1), _mm256_min_ps(x0, x1)),
                                           _mm256_max_ps(_mm256_min_ps(z0, z1), _mm256_setzero_ps()));
        const __m256 tFar = _mm256_min_ps(_mm256_min_ps(_mm256_max_ps(y0, y1), _mm256_max_ps(x0, x1)),
                                          _mm256_min_ps(_mm256_max_ps(z0, z1), bestV));
        const __m256 enters = _mm256_cmp_ps(tNear, tFar, _CMP_LE_OQ);
        const std::uint32_t hit = std::uint32_t(_mm256_movemask_ps(enters)) & lanes;
        if (!hit) continue;
        // Where each entering ray enters; +infinity in the other lanes.
        const __m256 t = _mm256_blendv_ps(infinity, tNear, enters);
        __m128 m = _mm_min_ps(_mm256_castps256_ps128(t), _mm256_extractf128_ps(t, 1));
        m = _mm_min_ps(m, _mm_movehl_ps(m, m));
        m = _mm_min_ss(m, _mm_shuffle_ps(m, m, 1));
        const float nearest = _mm_cvtss_f32(m);
        const PacketPending p{t, n.child[c], hit};
        std::size_t j = found++;
        for (; j > 0 && key[j - 1] < nearest; --j) {
          order[j] = order[j - 1];
          key[j] = key[j - 1];
        }
        order[j] = p;
        key[j] = nearest;
      }
      if (found) {  // farthest first in `order`: all but the nearest wait
        sp += found - 1;
        ref = stack[sp].ref;
        lanes = stack[sp].lanes;
        continue;
      }
    }
    // Next waiting child that a ray may still cross before its best.
    for (;;) {
      if (sp == 0) {
        for (unsigned k = 0; k < count; ++k) out[k] = best[k];
        return;
      }
      const PacketPending& p = stack[--sp];
      const std::uint32_t still =
          std::uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(p.t, _mm256_load_ps(bestT), _CMP_LE_OQ))) & p.lanes;
      if (still) {
        ref = p.ref;
        lanes = still;
        break;
      }
    }
  }
}

#else  // no AVX2 kernel in this build: never chosen (RayIndex::usesAvx2() is false)
Crossing castAvx2(const Arrays& index, const Ray& ray) { return castBaseline(index, ray); }
void castPacketAvx2(const Arrays& index, const Ray* rays, unsigned count, Crossing* out) {
  for (unsigned k = 0; k < count; ++k) out[k] = castBaseline(index, rays[k]);
}
#endif

}  // namespace cmkit::detail
