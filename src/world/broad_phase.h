// broad_phase.h: the world's broad phase, a bounding-volume tree over the
// world bounds of its entities (every entity but the world model, which
// every query asks). Built top down (median split of the box centres along
// the longest axis of their spread, at most kLeafSize entities a leaf);
// an entity that moves is refitted in place (its leaf's box and every box
// above it grow or shrink to their children's); adding or removing an entity
// rebuilds the tree (a few hundred entities: well under a millisecond).
// Queries only read it: any number of threads at once.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "cmkit/bounds.h"
#include "cmkit/world.h"

namespace cmkit::detail {

/// An entity as the tree holds it.
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

  /// Appends to `out` every entity whose box `overlaps` accepts, visiting
  /// only the subtrees whose box it accepts (`overlaps(const Bounds&)`).
  /// `stack` is scratch. Order: the tree's (callers sort
  /// when they need to).
  template <class Overlaps>
  void collect(const Overlaps& overlaps, std::vector<EntityId>& out, std::vector<std::int32_t>& stack) const {
    if (nodes_.empty()) return;
    stack.clear();
    if (overlaps(nodes_[0].bounds)) stack.push_back(0);
    // A node is pushed only once its box passed (children tested in place).
    while (!stack.empty()) {
      const Node& n = nodes_[std::size_t(stack.back())];
      stack.pop_back();
      if (n.count > 0) {
        for (std::int32_t k = n.first; k < n.first + n.count; ++k) {
          const BroadPhaseItem& item = items_[std::size_t(k)];
          if (overlaps(item.bounds)) out.push_back(item.id);
        }
        continue;
      }
      if (overlaps(nodes_[std::size_t(n.first + 1)].bounds)) stack.push_back(n.first + 1);
      if (overlaps(nodes_[std::size_t(n.first)].bounds)) stack.push_back(n.first);
    }
  }

  /// Number of entities in the tree.
  std::size_t size() const { return items_.size(); }

 private:
  /// count > 0: a leaf of items_[first, first + count); else an inner node
  /// whose children are nodes first and first + 1.
  struct Node {
    Bounds bounds;
    std::int32_t first = 0;
    std::int32_t count = 0;
    std::int32_t parent = -1;
  };
  /// Two a leaf: lt4's no-entity-near translations were fastest so (1, 4
  /// and 8 were slower; `cmkit bench --world`).
  static constexpr std::int32_t kLeafSize = 2;

  /// Fills node `self` over items_[begin, end), its children below it.
  void build(std::int32_t self, std::int32_t parent, std::int32_t begin, std::int32_t end);

  std::vector<Node> nodes_;
  std::vector<BroadPhaseItem> items_;
  std::vector<std::int32_t> leafOfId_;  ///< by entity id: its leaf node, -1 when not in the tree
  std::vector<std::int32_t> slotOfId_;  ///< by entity id: its index in items_
};

}  // namespace cmkit::detail
