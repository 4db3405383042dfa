// Pruning the world model with the renderer's BSP of the .proc file (the
// original's ChoppedAwayByProcBSP, docs/algorithms.md): a solid
// winding is dropped when every piece of it, split down the .proc tree, ends
// in an opaque solid leaf.
#include "cmkit/contents.h"
#include "compile/builder.h"

namespace cmkit::detail {

bool ModelBuilder::choppedAwayByProcBsp(const Winding& w, const Plane& plane, std::uint32_t contents) const {
  if (!proc_ || (contents & contents::kSolid) == 0) return false;
  // One bounding sphere of the whole winding, used for every piece: a node
  // farther than the radius from the centre sends the piece to one side
  // without splitting it.
  const Bounds bounds = w.bounds();
  Vec3 origin = (bounds.max - bounds.min) * Real(0.5);
  const Real radius = origin.length() + tol::kChopEpsilon;
  origin = bounds.min + origin;

  // The pieces still to walk down (the original recurses into the back
  // piece; the answer does not depend on the order: any piece reaching an
  // area keeps the winding).
  struct Piece {
    std::int32_t node;
    Winding winding;
  };
  std::vector<Piece> pending;
  pending.push_back({0, w});
  Winding back;
  while (!pending.empty()) {
    Piece piece = std::move(pending.back());
    pending.pop_back();
    std::int32_t nodeNum = piece.node;
    do {
      const ProcNode& node = proc_->nodes[static_cast<std::size_t>(nodeNum)];
      const Real dist = node.plane.distance(origin);
      Side side;
      if (dist > radius) {
        side = Side::Front;
      } else if (dist < -radius) {
        side = Side::Back;
      } else {
        side = piece.winding.split(back, node.plane, tol::kChopEpsilon);
      }
      if (side == Side::Front) {
        nodeNum = node.children[0];
      } else if (side == Side::Back) {
        nodeNum = node.children[1];
      } else if (side == Side::On) {
        // On the plane: the piece goes to the side its polygon faces.
        nodeNum = node.children[node.plane.normal.dot(plane.normal) > Real(0) ? 0 : 1];
      } else {
        // Cut: a piece next to an area keeps the winding; a solid back child
        // swallows the back piece; a node behind is walked later.
        if (node.children[0] < 0 || node.children[1] < 0) return false;
        if (node.children[1] > 0) pending.push_back({node.children[1], back});
        nodeNum = node.children[0];
      }
    } while (nodeNum > 0);
    if (nodeNum < 0) return false;  // this piece reaches an area
  }
  return true;
}

}  // namespace cmkit::detail
