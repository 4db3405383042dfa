// Chopping polygons by the brushes of the model (the original's
// WindingOutsideBrushes, R_ChopWindingListWithTreeBrushes and
// ChopWindingListWithBrush): parts of a polygon inside a brush of the same
// contents are removed.
#include "compile/builder.h"

namespace cmkit::detail {

const Winding* ModelBuilder::windingOutsideBrushes(const Winding& w, const Plane& plane,
                                                   std::uint32_t contents, int primitiveNum) {
  // No brush chops anything (a mesh, or an entity of patches only): the
  // list would end as the winding alone.
  if (brushes_.empty()) return &w;
  WindingList& list = list_;
  list.bounds = w.bounds();
  list.origin = (list.bounds.max - list.bounds.min) * Real(0.5);
  list.radius = list.origin.length() + tol::kChopEpsilon;
  list.origin = list.bounds.min + list.origin;
  list.bounds.min -= Vec3(tol::kChopEpsilon, tol::kChopEpsilon, tol::kChopEpsilon);
  list.bounds.max += Vec3(tol::kChopEpsilon, tol::kChopEpsilon, tol::kChopEpsilon);
  if (list.w.empty()) list.w.resize(kMaxWindings);
  list.w[0] = w;
  list.numWindings = 1;
  list.normal = plane.normal;
  list.contents = contents;
  list.primitiveNum = primitiveNum;

  ++checkCount_;
  chopWindingListWithTreeBrushes(0);

  if (list.numWindings == 0) return nullptr;
  if (list.numWindings == 1) return &list.w[0];
  // Several fragments: the world model keeps the one fragment the .proc BSP
  // does not chop away; otherwise (no .proc, not the world, or more than one
  // left) the whole winding. When every fragment would be chopped away the
  // whole winding stays too (the original's behaviour there is not known; the winding as
  // a whole was not chopped away).
  const Winding* left = nullptr;
  for (std::size_t k = 0; k < list.numWindings; ++k) {
    if (choppedAwayByProcBsp(list.w[k], plane, contents)) continue;
    if (left) return &w;
    left = &list.w[k];
  }
  return left ? left : &w;
}

void ModelBuilder::chopWindingListWithTreeBrushes(int nodeNum) {
  WindingList& list = list_;
  // (stopping once nothing is left changes nothing: later brushes would
  // only be marked)
  walkTouching(nodeNum, list.bounds, [&](int n) {
    for (const int bn : brushesAt(n)) {
      BBrush& b = brush(bn);
      if (b.checkcount == checkCount_) continue;
      b.checkcount = checkCount_;
      if (b.primitiveNum == list.primitiveNum) continue;  // the polygon's own brush
      if (b.contents != list.contents) continue;
      if (!b.bounds.intersects(list.bounds)) continue;
      // false: the list is left as it was by this brush (a fragment on a
      // same-facing brush side, or too many fragments); the walk goes on
      // (returning here instead gives other results than the reference).
      chopWindingListWithBrush(b);
    }
    return list.numWindings != 0;
  });
}

bool ModelBuilder::chopWindingListWithBrush(const BBrush& b) {
  WindingList& list = list_;
  const std::size_t numPlanes = b.planes.size();
  if (numPlanes > 64) return true;  // the original's fixed winding limit: not chopped
  const std::size_t kMax = kMaxWindings;
  if (outList_.empty()) outList_.resize(kMax);
  if (tmpList_.empty()) tmpList_.resize(kMax);
  auto tooManyWindings = [&] {
    warn("primitive " + std::to_string(list.primitiveNum) + " is chopped into more than " +
         std::to_string(kMax) + " windings");
    return false;
  };

  // The side of the whole list of each inward brush plane.
  Side sidedness[64];
  for (std::size_t i = 0; i < numPlanes; ++i) {
    const Plane plane = b.planes[i].flipped();
    const Real dist = plane.distance(list.origin);
    if (dist > list.radius) {
      sidedness[i] = Side::Front;
    } else if (dist < -list.radius) {
      sidedness[i] = Side::Back;
    } else {
      sidedness[i] = list.bounds.planeSide(plane, tol::kOnEpsilon);  // Front, Back or Cross
    }
  }

  std::size_t numOut = 0;
  Winding front;
  Winding back;
  for (std::size_t k = 0; k < list.numWindings; ++k) {
    std::size_t startPlane = 0;
    std::size_t bestNumWindings = 1 + numPlanes;
    bool chopped = false;
    do {
      front = list.w[k];
      std::size_t numTmp = 0;
      for (std::size_t planeNum = startPlane, i = 0; i < numPlanes; ++i, ++planeNum) {
        if (planeNum >= numPlanes) planeNum = 0;
        Side res = sidedness[planeNum];
        if (res == Side::Cross) res = front.split(back, b.planes[planeNum].flipped(), tol::kChopEpsilon);
        // A winding on a brush side facing the same way stays (coplanar
        // touching faces); all windings of the list are on that plane.
        if (res == Side::On && list.primitiveNum >= 0 && list.normal.dot(b.planes[planeNum].normal) > 0) {
          return false;
        }
        if (res == Side::Back) {
          if (numOut >= kMax) return tooManyWindings();
          // Outside this plane: the winding does not touch the brush.
          outList_[numOut] = list.w[k];
          ++numOut;
          chopped = false;
          break;
        }
        if (res == Side::Cross) {
          if (numTmp >= kMax) return tooManyWindings();
          tmpList_[numTmp] = back;  // the part outside the brush
          ++numTmp;
          chopped = true;
        }
        if (numTmp >= bestNumWindings) break;
      }
      // Keep the start plane that leaves the fewest fragments.
      if (numTmp < bestNumWindings) {
        bestNumWindings = numTmp;
        for (std::size_t i = 0; i < numTmp; ++i) {
          if (numOut + i >= kMax) return tooManyWindings();
          outList_[numOut + i] = tmpList_[i];
        }
        if (bestNumWindings == 1) break;
      }
      ++startPlane;
    } while (chopped && startPlane < numPlanes);
    if (chopped) numOut += bestNumWindings;
  }
  for (std::size_t k = 0; k < numOut; ++k) list.w[k] = outList_[k];
  list.numWindings = numOut;
  return true;
}

}  // namespace cmkit::detail
