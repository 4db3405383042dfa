// A node's split plane while the axial BSP tree grows (the original's
// CM_FindSplitter): the most centred bounds plane of the node's items and of
// its ancestors', searched four items at a time where lanes are float.
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "compile/builder.h"
#include "compile/growing_lists.h"
#include "util/simd.h"

namespace cmkit::detail {

namespace {

/// t of a splitter candidate at `dist` in a node spanning lo..hi: how far
/// it is from the middle (twice that), as the original computes it.
inline Real splitterT(Real lo, Real hi, Real dist) { return std::fabs((hi - dist) - (dist - lo)); }

/// The original's search, one candidate at a time in list order (each list
/// from its head, the end of its array; an item's min before its max): the
/// first candidate strictly inside lo..hi with the least t below `size`.
template <class Source>
bool firstMostCentred(const std::vector<Source>& sources, int type, Real lo, Real hi, Real size,
                      Real& bestDist) {
  Real bestt = size;
  bestDist = 0;
  for (const Source& source : sources) {
    for (std::size_t k = source.count; k-- > 0;) {
      const auto* it = source.items + k;
      for (const Real dist : {it->bounds.min[type], it->bounds.max[type]}) {
        const Real t = splitterT(lo, hi, dist);
        const bool better = (dist < hi) & (dist > lo) & (t < bestt);
        bestt = better ? t : bestt;
        bestDist = better ? dist : bestDist;
      }
    }
  }
  return bestt < size;
}

/// The splitter firstMostCentred finds. With float lanes, four items at a
/// time in any order: per lane the least t, the plane that gave it first and
/// whether another plane gave the same t; only the position in list order
/// tells apart two planes with the least t, so then (rarely) the search in
/// list order decides.
template <class Source>
bool mostCentredSplitter(const std::vector<Source>& sources, int type, Real lo, Real hi, Real size,
                         Real& bestDist) {
#ifdef CMKIT_FLOAT_LANES
  using simd::F4;
  const F4 loV = F4::all(lo), hiV = F4::all(hi), sizeV = F4::all(size);
  F4 best = sizeV, bestD = F4::zero(), tied = F4::zero();
  auto candidates = [&](F4 d) {
    // t, or a NaN (all bits set) where d is not strictly inside lo..hi: no
    // comparison holds for it. (A lane still at `size` may be marked tied
    // by a plane with t == size, which is no candidate; such a lane is
    // never the least, or its mark is cleared by the next less.)
    const F4 outside = (d >= hiV) | (d <= loV);
    const F4 t = simd::abs((hiV - d) - (d - loV)) | outside;
    const F4 less = t < best;
    const F4 same = simd::andNot(simd::sameBits(d, bestD), t == best);  // (another plane, the same t)
    tied = simd::andNot(less, tied | same);
    best = simd::min(t, best);  // (best where t is a NaN or not less)
    bestD = simd::select(less, d, bestD);
  };
  // An item's bounds from coordinate `type` of min on: lane 0 is min[type],
  // lane 3 max[type] (the bounds are six floats; these 16 bytes lie within).
  static_assert(sizeof(Bounds) == 6 * sizeof(float));
  const std::size_t offset = static_cast<std::size_t>(type) * sizeof(float);
  auto row = [offset](const auto& item) {
    alignas(16) float f[4];
    std::memcpy(f, reinterpret_cast<const char*>(&item.bounds) + offset, sizeof f);
    return F4::load(f);
  };
  for (const Source& source : sources) {
    const auto* it = source.items;
    const std::size_t n = source.count;
    std::size_t k = 0;
    for (; k + 4 <= n; k += 4) {
      F4 mins = row(it[k]), r1 = row(it[k + 1]), r2 = row(it[k + 2]), maxs = row(it[k + 3]);
      simd::transpose(mins, r1, r2, maxs);
      candidates(mins);
      candidates(maxs);
    }
    if (k < n) {  // the rest (one to three items) as one block, lo in the lanes left (never inside)
      F4 mins = row(it[k]), r1 = k + 1 < n ? row(it[k + 1]) : loV, r2 = k + 2 < n ? row(it[k + 2]) : loV,
         maxs = loV;
      simd::transpose(mins, r1, r2, maxs);
      candidates(mins);
      candidates(maxs);
    }
  }
  const float least = simd::lowest(best);
  if (!(least < size)) {
    bestDist = 0;
    return false;
  }
  alignas(16) float bests[4], dists[4], ties[4];  // (ties: masks, 0 where clear)
  best.store(bests);
  bestD.store(dists);
  tied.store(ties);
  bool first = true;
  bool unique = true;
  for (int j = 0; j < 4; ++j) {
    if (bests[j] != least) continue;
    unique = unique && ties[j] == 0 &&
             (first || std::bit_cast<std::uint32_t>(dists[j]) == std::bit_cast<std::uint32_t>(bestDist));
    if (first) bestDist = dists[j];
    first = false;
  }
  if (unique) return true;
#endif
  return firstMostCentred(sources, type, lo, hi, size, bestDist);
}
}  // namespace

bool ModelBuilder::findSplitter(GrowingLists& lists, int nodeNum, const Bounds& bounds, int& planeType,
                                Real& planeDist) const {
  Real size[3];
  int axis[3];
  for (int i = 0; i < 3; ++i) {
    size[i] = bounds.max[i] - bounds.min[i];
    axis[i] = i;
  }
  // Largest axis first, equal sizes in axis order: what the original's
  // restarting bubble sort gives, as three compare-and-swaps in registers
  // (the loop kept the sizes in memory, and its restarts mispredicted).
  auto order = [&](int i) {
    const bool swap = size[i] < size[i + 1];
    const Real s0 = swap ? size[i + 1] : size[i], s1 = swap ? size[i] : size[i + 1];
    const int a0 = swap ? axis[i + 1] : axis[i], a1 = swap ? axis[i] : axis[i + 1];
    size[i] = s0, size[i + 1] = s1, axis[i] = a0, axis[i + 1] = a1;
  };
  order(0);
  order(1);
  order(0);
  bool forceSplit = false;
  if (size[0] < tol::kMinNodeSize) {
    const GrowingLists::Span& span = lists.polygons.at[static_cast<std::size_t>(nodeNum)];
    std::size_t polyCount = 0;
    for (std::uint32_t k = 0; k < span.count; ++k)
      polyCount += GrowingLists::itemsOf(lists.polygons.data(span)[k].item);
    if (polyCount > static_cast<std::size_t>(tol::kMaxNodePolygons)) forceSplit = true;
  }
  for (int i = 0; i < 3; ++i) {
    const int type = axis[i];
    if (!forceSplit && size[i] < tol::kMinNodeSize) break;
    if (i == 0) {
      // candidates from the brushes, then the polygons, of this node and its ancestors
      lists.sources.clear();
      for (const GrowingLists::Kind* kind : {&lists.brushes, &lists.polygons}) {
        auto addSource = [&](int n) {
          const GrowingLists::Span& span = kind->at[static_cast<std::size_t>(n)];
          if (span.count != 0) lists.sources.push_back({kind->data(span), span.count});
        };
        addSource(nodeNum);
        for (auto a = lists.filledAncestors.rbegin(); a != lists.filledAncestors.rend(); ++a)
          addSource(lists.ancestors[*a]);
      }
    }
    // The most centred splitter (dhewm3: not truncated to an integer): the
    // first bounds plane strictly inside the node with the least t, each
    // list from its head (the end of its array).
    Real bestDist = 0;
    const bool found =
        mostCentredSplitter(lists.sources, type, bounds.min[type], bounds.max[type], size[i], bestDist);
    if (found) {
      planeType = type;
      planeDist = bestDist;
      if (forceSplit) return true;
      // not too close to the node bounds
      if (bounds.max[type] - planeDist > tol::kSplitterMinDistance &&
          planeDist - bounds.min[type] > tol::kSplitterMinDistance) {
        return true;
      }
    }
  }
  return false;
}

}  // namespace cmkit::detail
