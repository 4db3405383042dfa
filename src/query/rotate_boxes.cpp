// The boxes of a rotation: the box of a point's arc (arcBounds), the arc
// boxes of the trace model's vertices (vertexArcBoxes), and the culls of
// feature boxes against a polygon's bounds and plane (boxesCrossing,
// boxesTouching).
//
// Float lanes where util/simd.h has them (boxesCrossing, boxesTouching: four
// feature boxes at a time; vertexArcBoxes: four vertices' arc boxes at once);
// other builds (another target, -DCMKIT_NO_SIMD, CMKIT_DOUBLE) use the
// portable loops, which do the same arithmetic.
#include <bit>
#include <cmath>

#include "query/rotate_work.h"
#include "util/simd.h"
#ifdef CMKIT_FLOAT_LANES
#define CMKIT_ROTATE_SSE2 1
#endif

namespace cmkit::detail {

Bounds arcBounds(const Vec3& ro, const Vec3& axis, const Vec3& p, const Vec3& end) {
  Bounds b = Bounds::ofPoint(p);
  b.addPoint(end);
  const Vec3 m1 = (p - ro).cross(axis);
  const Vec3 m2 = (end - ro).cross(axis);
  const Real radiusSq = (p - ro).lengthSquared();
  for (int i = 0; i < 3; ++i) {
    // The motion along this axis changes sign: the arc passes the circle's
    // extreme on the side of the chord's midpoint (arcs below 180 degrees).
    if ((m1[i] > 0 && m2[i] < 0) || (m1[i] < 0 && m2[i] > 0)) {
      const Real extent = std::sqrt(std::max(Real(0), radiusSq * (Real(1) - axis[i] * axis[i])));
      if (Real(0.5) * (p[i] + end[i]) - ro[i] > 0)
        b.max[i] = std::max(b.max[i], ro[i] + extent);
      else
        b.min[i] = std::min(b.min[i], ro[i] - extent);
    }
  }
  return b;
}

Bounds vertexArcBoxes(VertexArcs& arcs, int n, const Vec3& axis, FeatureBoxes& boxes) {
#ifdef CMKIT_ROTATE_SSE2
  // Four vertices at a time, one coordinate per register: arcBounds'
  // arithmetic in each lane (the same operations in the same order, so the
  // same bits; the choices of its branches made by masks). The lanes past n
  // repeat the last vertex (its box again: the union is the same).
  for (std::size_t i = std::size_t(n); i % 4 != 0; ++i) {
    const std::size_t last = std::size_t(n - 1);
    arcs.set(i, {arcs.px[last], arcs.py[last], arcs.pz[last]}, {arcs.ex[last], arcs.ey[last], arcs.ez[last]},
             {arcs.rx[last], arcs.ry[last], arcs.rz[last]});
  }
  using simd::F4, simd::min, simd::max, simd::andNot, simd::lowest, simd::highest;
  const F4 zero = F4::zero(), half = F4::all(0.5f), eps = F4::all(tol::kBoxEpsilon);
  const F4 ax = F4::all(axis.x), ay = F4::all(axis.y), az = F4::all(axis.z);
  const F4 one = F4::all(1);
  const F4 offX = one - ax * ax, offY = one - ay * ay, offZ = one - az * az;
  F4 uLoX = F4::all(tol::kBoundsInfinity), uLoY = uLoX, uLoZ = uLoX;
  F4 uHiX = F4::all(-tol::kBoundsInfinity), uHiY = uHiX, uHiZ = uHiX;
  for (std::size_t i = 0; i < std::size_t(n); i += 4) {
    const F4 px = F4::load(&arcs.px[i]), py = F4::load(&arcs.py[i]), pz = F4::load(&arcs.pz[i]);
    const F4 ex = F4::load(&arcs.ex[i]), ey = F4::load(&arcs.ey[i]), ez = F4::load(&arcs.ez[i]);
    const F4 rx = F4::load(&arcs.rx[i]), ry = F4::load(&arcs.ry[i]), rz = F4::load(&arcs.rz[i]);
    // (p - ro) x axis and (end - ro) x axis, Vec3::cross term for term.
    const F4 dx = px - rx, dy = py - ry, dz = pz - rz;
    const F4 fx = ex - rx, fy = ey - ry, fz = ez - rz;
    const F4 m1x = dy * az - dz * ay, m1y = dz * ax - dx * az, m1z = dx * ay - dy * ax;
    const F4 m2x = fy * az - fz * ay, m2y = fz * ax - fx * az, m2z = fx * ay - fy * ax;
    const F4 radiusSq = dx * dx + dy * dy + dz * dz;
    // One axis of arcBounds, for four vertices.
    auto axisBox = [&](F4 m1, F4 m2, F4 off, F4 p, F4 e, F4 ro, F4& loOut, F4& hiOut) {
      const F4 turns = ((m1 > zero) & (m2 < zero)) | ((m1 < zero) & (m2 > zero));
      const F4 extent = simd::sqrt(max(radiusSq * off, zero));
      const F4 up = half * (p + e) - ro > zero;
      const F4 lo = min(e, p), hi = max(e, p);  // Bounds::ofPoint(p).addPoint(e)
      const F4 top = max(ro + extent, hi);
      const F4 bottom = min(ro - extent, lo);
      const F4 raise = turns & up, lower = andNot(up, turns);
      hiOut = ((raise & top) | andNot(raise, hi)) + eps;
      loOut = ((lower & bottom) | andNot(lower, lo)) - eps;
    };
    F4 lo, hi;
    axisBox(m1x, m2x, offX, px, ex, rx, lo, hi);
    lo.store(&boxes.minX[i]), hi.store(&boxes.maxX[i]);
    uLoX = min(lo, uLoX), uHiX = max(hi, uHiX);
    axisBox(m1y, m2y, offY, py, ey, ry, lo, hi);
    lo.store(&boxes.minY[i]), hi.store(&boxes.maxY[i]);
    uLoY = min(lo, uLoY), uHiY = max(hi, uHiY);
    axisBox(m1z, m2z, offZ, pz, ez, rz, lo, hi);
    lo.store(&boxes.minZ[i]), hi.store(&boxes.maxZ[i]);
    uLoZ = min(lo, uLoZ), uHiZ = max(hi, uHiZ);
  }
  return {{lowest(uLoX), lowest(uLoY), lowest(uLoZ)}, {highest(uHiX), highest(uHiY), highest(uHiZ)}};
#else
  Bounds all;
  for (std::size_t i = 0; i < std::size_t(n); ++i) {
    const Bounds box = arcBounds({arcs.rx[i], arcs.ry[i], arcs.rz[i]}, axis,
                                 {arcs.px[i], arcs.py[i], arcs.pz[i]}, {arcs.ex[i], arcs.ey[i], arcs.ez[i]})
                           .expanded(tol::kBoxEpsilon);
    boxes.set(i, box);
    all.addBounds(box);
  }
  return all;
#endif
}

#ifdef CMKIT_ROTATE_SSE2
namespace {
using simd::F4;
/// A box in four lanes, for the box tests of four feature boxes at a time.
struct BoxLanes {
  explicit BoxLanes(const Bounds& b)
      : loX(F4::all(b.min.x)),
        loY(F4::all(b.min.y)),
        loZ(F4::all(b.min.z)),
        hiX(F4::all(b.max.x)),
        hiY(F4::all(b.max.y)),
        hiZ(F4::all(b.max.z)) {}
  /// Lane k: feature box i + k lies apart from this box (Bounds::intersects
  /// false, by the same comparisons).
  F4 apart(const FeatureBoxes& f, std::size_t i) const {
    return ((hiX < F4::load(&f.minX[i])) | (hiY < F4::load(&f.minY[i])) | (hiZ < F4::load(&f.minZ[i]))) |
           ((loX > F4::load(&f.maxX[i])) | (loY > F4::load(&f.maxY[i])) | (loZ > F4::load(&f.maxZ[i])));
  }
  F4 loX, loY, loZ, hiX, hiY, hiZ;
};
}  // namespace
#endif

std::uint32_t boxesCrossing(const FeatureBoxes& b, int n, const Bounds& bounds, const Plane& plane) {
#ifdef CMKIT_ROTATE_SSE2
  {
    // Four boxes at a time: Bounds::intersects and Bounds::planeSide's
    // arithmetic in the same order in each lane (the same bits); lanes past
    // n are masked off.
    const F4 half = F4::all(0.5f), dist = F4::all(plane.dist);
    const Vec3& nm = plane.normal;
    const F4 nx = F4::all(nm.x), ny = F4::all(nm.y), nz = F4::all(nm.z);
    const F4 eps = F4::all(tol::kOnEpsilon), negEps = F4::all(-tol::kOnEpsilon);
    const BoxLanes box(bounds);
    std::uint32_t rejected = 0;
    for (std::size_t i = 0; i < std::size_t(n); i += 4) {
      const F4 mnX = F4::load(&b.minX[i]), mnY = F4::load(&b.minY[i]), mnZ = F4::load(&b.minZ[i]);
      const F4 mxX = F4::load(&b.maxX[i]), mxY = F4::load(&b.maxY[i]), mxZ = F4::load(&b.maxZ[i]);
      const F4 cx = (mnX + mxX) * half, cy = (mnY + mxY) * half, cz = (mnZ + mxZ) * half;
      const F4 d1 = nx * cx + ny * cy + nz * cz - dist;
      const F4 d2 = simd::abs((mxX - cx) * nx) + simd::abs((mxY - cy) * ny) + simd::abs((mxZ - cz) * nz);
      const F4 oneSide = (d1 - d2 > eps) | (d1 + d2 < negEps);
      rejected |= std::uint32_t(simd::bits(oneSide | box.apart(b, i))) << i;
    }
    const std::uint32_t all = n >= 32 ? ~std::uint32_t(0) : (std::uint32_t(1) << n) - 1;
    return ~rejected & all;
  }
#endif
  // Elsewhere (and -DCMKIT_NO_SIMD): Bounds' own tests, box by box.
  std::uint32_t bits = 0;
  for (std::size_t i = 0; i < std::size_t(n); ++i) {
    const Bounds box = b.get(i);
    bits |= std::uint32_t(box.intersects(bounds) && box.planeSide(plane) == Side::Cross) << i;
  }
  return bits;
}

std::uint32_t boxesTouching(const FeatureBoxes& b, std::uint32_t candidates, const Bounds& bounds) {
#ifdef CMKIT_ROTATE_SSE2
  // Four boxes at a time, up to the last candidate (BoxLanes::apart).
  const BoxLanes box(bounds);
  std::uint32_t apart = 0;
  for (std::size_t i = 0; i < 32 && (candidates >> i) != 0; i += 4)
    apart |= std::uint32_t(simd::bits(box.apart(b, i))) << i;
  return candidates & ~apart;
#else
  std::uint32_t bits = 0;
  for (; candidates; candidates &= candidates - 1) {
    const auto i = std::size_t(std::countr_zero(candidates));
    bits |= std::uint32_t(boxesTouch(b.get(i), bounds)) << i;  // (no branches: unpredictable)
  }
  return bits;
#endif
}

}  // namespace cmkit::detail
