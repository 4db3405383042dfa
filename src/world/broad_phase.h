// broad_phase.h: the world's broad phase, a 4-wide bounding-volume tree over
// the world bounds of its entities (every entity but the world model, which
// every query asks). A node holds the boxes of up to four children, each an
// entity or another node, stored coordinate by coordinate (minX of the four,
// minY of the four, ...) so that a box query tests all four at once
// (src/util/simd.h; the portable path tests them one at a time, with the same
// comparisons). Built top down: the items are split in two at the median of
// their box centres along the longest axis of the centres' spread, and each
// half so again, giving four groups; a group of one entity is a child
// entity, a larger one a child node. An entity that moves is refitted in
// place (its box in its node, and every box above it, grow or shrink to what
// they hold; the tree's shape stays); adding or removing an entity rebuilds
// the tree (a few hundred entities: well under a millisecond). Queries only
// read it: any number of threads at once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/bounds.h"
#include "cmkit/world.h"
#include "util/assert.h"

namespace cmkit::detail {

/// An entity as the tree is built from it.
struct BroadPhaseItem {
  EntityId id = kNoEntity;  ///< the entity
  Bounds bounds;            ///< its world bounds
};

/// The broad phase's tree. Ids must be >= 0.
class BroadPhase {
 public:
  /// Builds the tree over `items` (entities with cleared bounds are left out:
  /// nothing can touch them).
  void rebuild(std::span<const BroadPhaseItem> items);
  /// Sets the bounds of an entity in the tree and refits the boxes above it.
  /// An entity not in the tree (cleared bounds when built): false, the
  /// caller rebuilds.
  bool refit(EntityId id, const Bounds& bounds);

  /// Appends to `out` every entity whose box meets `box` (Bounds::intersects:
  /// touching counts), in the tree's order (callers sort when they need to).
  void collectBox(const Bounds& box, std::vector<EntityId>& out) const;

  /// Appends to `out` every entity whose box `overlaps` accepts, visiting
  /// only the subtrees whose box it accepts (`overlaps(const Bounds&)`).
  /// Order: the tree's.
  template <class Overlaps>
  void collect(const Overlaps& overlaps, std::vector<EntityId>& out) const {
    if (nodes_.empty()) return;
    Walk walk;
    walk.push(0);
    while (!walk.empty()) {
      const Node& n = nodes_[std::size_t(walk.pop())];
      for (int lane = 0; lane < n.count; ++lane)
        if (overlaps(n.laneBounds(lane))) visit(n.child[lane], out, walk);
    }
  }

  /// Number of entities in the tree.
  std::size_t size() const { return size_; }

 private:
  /// Up to four children, lanes [0, count); the other lanes' boxes are
  /// cleared (min +infinity, max -infinity: no box meets them).
  struct Node {
    alignas(16) Real minX[4];
    alignas(16) Real minY[4];
    alignas(16) Real minZ[4];
    alignas(16) Real maxX[4];
    alignas(16) Real maxY[4];
    alignas(16) Real maxZ[4];
    /// >= 0: a child node's index; < 0: the entity ~child.
    std::int32_t child[4] = {0, 0, 0, 0};
    std::int32_t count = 0;
    std::int32_t parent = -1;      ///< -1 at the root
    std::int32_t parentLane = -1;  ///< the lane of this node in its parent

    Node();  ///< no lanes, every box cleared
    Bounds laneBounds(int lane) const {
      return {{minX[lane], minY[lane], minZ[lane]}, {maxX[lane], maxY[lane], maxZ[lane]}};
    }
    void setLane(int lane, const Bounds& b);
    /// The box around the node's lanes.
    Bounds bounds() const;
  };

  /// The nodes still to visit. A node pushes at most four children and the
  /// median splits make the depth at most log4(n) + 1 (every group holds at
  /// most ceil(n / 4) items): 17 levels for 2^31 entities, so at most
  /// 3 * 17 + 1 entries wait at once.
  struct Walk {
    std::int32_t nodes[64];
    int size = 0;
    void push(std::int32_t n) {
      CMKIT_ASSERT(size < 64);
      nodes[size++] = n;
    }
    std::int32_t pop() { return nodes[--size]; }
    bool empty() const { return size == 0; }
  };

  static void visit(std::int32_t child, std::vector<EntityId>& out, Walk& walk) {
    if (child < 0)
      out.push_back(~child);
    else
      walk.push(child);
  }

  /// Fills node `self` over items[begin, end) (more than one item).
  void build(std::vector<BroadPhaseItem>& items, std::int32_t self, std::size_t begin, std::size_t end);

  std::vector<Node> nodes_;  ///< nodes_[0]: the root
  std::size_t size_ = 0;
  /// By entity id: the node holding it (-1 when not in the tree) and its lane.
  std::vector<std::int32_t> nodeOfId_;
  std::vector<std::int32_t> laneOfId_;
};

}  // namespace cmkit::detail
