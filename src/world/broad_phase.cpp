// The world's broad-phase tree (broad_phase.h).
#include "world/broad_phase.h"

#include <algorithm>

namespace cmkit::detail {

void BroadPhase::rebuild(std::span<const BroadPhaseItem> items) {
  nodes_.clear();
  items_.clear();
  leafOfId_.clear();
  slotOfId_.clear();
  for (const BroadPhaseItem& item : items)
    if (!item.bounds.isCleared()) items_.push_back(item);
  if (items_.empty()) return;
  EntityId maxId = 0;
  for (const BroadPhaseItem& item : items_) maxId = std::max(maxId, item.id);
  leafOfId_.assign(std::size_t(maxId) + 1, -1);
  slotOfId_.assign(std::size_t(maxId) + 1, -1);
  nodes_.reserve(2 * items_.size() / std::size_t(kLeafSize) + 2);
  nodes_.emplace_back();
  build(0, -1, 0, std::int32_t(items_.size()));
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    for (std::int32_t k = n.first; n.count > 0 && k < n.first + n.count; ++k) {
      leafOfId_[std::size_t(items_[std::size_t(k)].id)] = std::int32_t(i);
      slotOfId_[std::size_t(items_[std::size_t(k)].id)] = k;
    }
  }
}

void BroadPhase::build(std::int32_t self, std::int32_t parent, std::int32_t begin, std::int32_t end) {
  Bounds box, centres;
  for (std::int32_t k = begin; k < end; ++k) {
    box.addBounds(items_[std::size_t(k)].bounds);
    centres.addPoint(items_[std::size_t(k)].bounds.center());
  }
  nodes_[std::size_t(self)].bounds = box;
  nodes_[std::size_t(self)].parent = parent;
  if (end - begin <= kLeafSize) {
    nodes_[std::size_t(self)].first = begin;
    nodes_[std::size_t(self)].count = end - begin;
    return;
  }
  // Median split along the longest axis of the centres' spread; equal
  // centres are ordered by id, so the tree depends only on the items.
  const Vec3 spread = centres.size();
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
  const std::int32_t mid = begin + (end - begin) / 2;
  std::nth_element(items_.begin() + begin, items_.begin() + mid, items_.begin() + end,
                   [axis](const BroadPhaseItem& a, const BroadPhaseItem& b) {
                     const Real ca = a.bounds.min[axis] + a.bounds.max[axis];
                     const Real cb = b.bounds.min[axis] + b.bounds.max[axis];
                     return ca < cb || (ca == cb && a.id < b.id);
                   });
  // The two children sit side by side (first, first + 1).
  const auto first = std::int32_t(nodes_.size());
  nodes_[std::size_t(self)].first = first;
  nodes_[std::size_t(self)].count = 0;
  nodes_.emplace_back();
  nodes_.emplace_back();
  build(first, self, begin, mid);
  build(first + 1, self, mid, end);
}

bool BroadPhase::refit(EntityId id, const Bounds& bounds) {
  if (id < 0 || std::size_t(id) >= leafOfId_.size() || leafOfId_[std::size_t(id)] < 0 || bounds.isCleared())
    return false;
  items_[std::size_t(slotOfId_[std::size_t(id)])].bounds = bounds;
  for (std::int32_t n = leafOfId_[std::size_t(id)]; n >= 0; n = nodes_[std::size_t(n)].parent) {
    Node& node = nodes_[std::size_t(n)];
    Bounds box;
    if (node.count > 0) {
      for (std::int32_t k = node.first; k < node.first + node.count; ++k)
        box.addBounds(items_[std::size_t(k)].bounds);
    } else {
      box.addBounds(nodes_[std::size_t(node.first)].bounds);
      box.addBounds(nodes_[std::size_t(node.first + 1)].bounds);
    }
    node.bounds = box;
  }
  return true;
}

}  // namespace cmkit::detail
