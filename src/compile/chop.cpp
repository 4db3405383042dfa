// Chopping polygons by the brushes of the model (the original's
// WindingOutsideBrushes, R_ChopWindingListWithTreeBrushes and
// ChopWindingListWithBrush): parts of a polygon inside a brush of the same
// contents are removed.
#include "compile/builder.h"

namespace cmkit::detail {

const Winding* ModelBuilder::windingOutsideBrushes(const Winding& w, const Plane& plane,
                                                   std::uint32_t contents, int primitiveNum) {
  WindingList& list = list_;
  list.bounds = w.bounds();
  list.origin = (list.bounds.max - list.bounds.min) * Real(0.5);
  list.radius = list.origin.length() + tol::kChopEpsilon;
  list.origin = list.bounds.min + list.origin;
  list.bounds.min -= Vec3(tol::kChopEpsilon, tol::kChopEpsilon, tol::kChopEpsilon);
  list.bounds.max += Vec3(tol::kChopEpsilon, tol::kChopEpsilon, tol::kChopEpsilon);
  if (list.w.empty()) list.w.resize(static_cast<std::size_t>(tol::kMaxWindingList));
  list.w[0] = w;
  list.numWindings = 1;
  list.normal = plane.normal;
  list.contents = contents;
  list.primitiveNum = primitiveNum;

  ++checkCount_;
  chopWindingListWithTreeBrushes(0);

  if (list.numWindings == 0) return nullptr;
  if (list.numWindings == 1) return &list.w[0];
  // Several fragments: without a proc BSP to remove some of them the
  // original keeps the whole winding.
  return &w;
}

void ModelBuilder::chopWindingListWithTreeBrushes(int nodeNum) {
  WindingList& list = list_;
  for (;;) {
    const BNode& node = nodes_[static_cast<std::size_t>(nodeNum)];
    for (int r = node.brushes; r >= 0; r = brushRefs_[static_cast<std::size_t>(r)].next) {
      BBrush& b = brushes_[static_cast<std::size_t>(brushRefs_[static_cast<std::size_t>(r)].item)];
      if (b.checkcount == checkCount_) continue;
      b.checkcount = checkCount_;
      if (b.primitiveNum == list.primitiveNum) continue;  // the polygon's own brush
      if (b.contents != list.contents) continue;
      int i = 0;
      for (; i < 3; ++i) {
        if (list.bounds.min[i] > b.bounds.max[i]) break;
        if (list.bounds.max[i] < b.bounds.min[i]) break;
      }
      if (i < 3) continue;
      // false: the list is left as it was by this brush (a fragment on a
      // same-facing brush side, or too many fragments); the walk goes on
      // (returning here instead gives other results than the reference).
      chopWindingListWithBrush(b);
    }
    if (node.planeType == -1) break;
    if (list.bounds.min[node.planeType] > node.planeDist) {
      nodeNum = node.children[0];
    } else if (list.bounds.max[node.planeType] < node.planeDist) {
      nodeNum = node.children[1];
    } else {
      const int front = node.children[0];
      chopWindingListWithTreeBrushes(node.children[1]);
      if (list.numWindings == 0) return;
      nodeNum = front;
    }
  }
}

bool ModelBuilder::chopWindingListWithBrush(const BBrush& b) {
  WindingList& list = list_;
  const int numPlanes = static_cast<int>(b.planes.size());
  if (numPlanes > 64) return true;  // the original's fixed winding limit: not chopped
  const int kMax = tol::kMaxWindingList;
  if (outList_.empty()) outList_.resize(static_cast<std::size_t>(kMax));
  if (tmpList_.empty()) tmpList_.resize(static_cast<std::size_t>(kMax));

  // The side of the whole list of each inward brush plane.
  Side sidedness[64];
  for (int i = 0; i < numPlanes; ++i) {
    const Plane plane = b.planes[static_cast<std::size_t>(i)].flipped();
    const Real dist = plane.distance(list.origin);
    if (dist > list.radius) {
      sidedness[i] = Side::Front;
    } else if (dist < -list.radius) {
      sidedness[i] = Side::Back;
    } else {
      sidedness[i] = list.bounds.planeSide(plane, tol::kOnEpsilon);  // Front, Back or Cross
    }
  }

  int numOut = 0;
  Winding front;
  Winding back;
  for (int k = 0; k < list.numWindings; ++k) {
    int startPlane = 0;
    int bestNumWindings = 1 + numPlanes;
    bool chopped = false;
    do {
      front = list.w[static_cast<std::size_t>(k)];
      int numTmp = 0;
      for (int planeNum = startPlane, i = 0; i < numPlanes; ++i, ++planeNum) {
        if (planeNum >= numPlanes) planeNum = 0;
        Side res = sidedness[planeNum];
        if (res == Side::Cross) {
          res = front.split(back, b.planes[static_cast<std::size_t>(planeNum)].flipped(), tol::kChopEpsilon);
        }
        // A winding on a brush side facing the same way stays (coplanar
        // touching faces); all windings of the list are on that plane.
        if (res == Side::On && list.primitiveNum >= 0 &&
            list.normal.dot(b.planes[static_cast<std::size_t>(planeNum)].normal) > 0) {
          return false;
        }
        if (res == Side::Back) {
          if (numOut >= kMax) {
            warn("primitive " + std::to_string(list.primitiveNum) + " is chopped into more than " +
                 std::to_string(kMax) + " windings");
            return false;
          }
          // Outside this plane: the winding does not touch the brush.
          outList_[static_cast<std::size_t>(numOut)] = list.w[static_cast<std::size_t>(k)];
          ++numOut;
          chopped = false;
          break;
        }
        if (res == Side::Cross) {
          if (numTmp >= kMax) {
            warn("primitive " + std::to_string(list.primitiveNum) + " is chopped into more than " +
                 std::to_string(kMax) + " windings");
            return false;
          }
          tmpList_[static_cast<std::size_t>(numTmp)] = back;  // the part outside the brush
          ++numTmp;
          chopped = true;
        }
        if (numTmp >= bestNumWindings) break;
      }
      // Keep the start plane that leaves the fewest fragments.
      if (numTmp < bestNumWindings) {
        bestNumWindings = numTmp;
        for (int i = 0; i < numTmp; ++i) {
          if (numOut + i >= kMax) {
            warn("primitive " + std::to_string(list.primitiveNum) + " is chopped into more than " +
                 std::to_string(kMax) + " windings");
            return false;
          }
          outList_[static_cast<std::size_t>(numOut + i)] = tmpList_[static_cast<std::size_t>(i)];
        }
        if (bestNumWindings == 1) break;
      }
      ++startPlane;
    } while (chopped && startPlane < numPlanes);
    if (chopped) numOut += bestNumWindings;
  }
  for (int k = 0; k < numOut; ++k)
    list.w[static_cast<std::size_t>(k)] = outList_[static_cast<std::size_t>(k)];
  list.numWindings = numOut;
  return true;
}

}  // namespace cmkit::detail
