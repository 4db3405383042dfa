// The world's broad-phase tree (broad_phase.h).
#include "world/broad_phase.h"

#include <algorithm>
#include <bit>

#include "util/simd.h"

namespace cmkit::detail {

namespace {

/// Orders items[begin, end) so that the median of their box centres along
/// the longest axis of the centres' spread sits at the middle; returns the
/// middle. Equal centres are ordered by id: the tree depends only on the
/// items.
std::size_t splitAtMedian(std::vector<BroadPhaseItem>& items, std::size_t begin, std::size_t end) {
  Bounds centres;
  for (std::size_t k = begin; k < end; ++k) centres.addPoint(items[k].bounds.center());
  const Vec3 spread = centres.size();
  const int axis = spread.x >= spread.y && spread.x >= spread.z ? 0 : (spread.y >= spread.z ? 1 : 2);
  const std::size_t mid = begin + (end - begin) / 2;
  using Diff = std::vector<BroadPhaseItem>::difference_type;
  std::nth_element(items.begin() + Diff(begin), items.begin() + Diff(mid), items.begin() + Diff(end),
                   [axis](const BroadPhaseItem& a, const BroadPhaseItem& b) {
                     const Real ca = a.bounds.min[axis] + a.bounds.max[axis];
                     const Real cb = b.bounds.min[axis] + b.bounds.max[axis];
                     return ca < cb || (ca == cb && a.id < b.id);
                   });
  return mid;
}

}  // namespace

void BroadPhase::Node::setLane(int lane, const Bounds& b) {
  minX[lane] = b.min.x;
  minY[lane] = b.min.y;
  minZ[lane] = b.min.z;
  maxX[lane] = b.max.x;
  maxY[lane] = b.max.y;
  maxZ[lane] = b.max.z;
}

BroadPhase::Node::Node() {
  for (int lane = 0; lane < 4; ++lane) setLane(lane, Bounds{});
}

Bounds BroadPhase::Node::bounds() const {
  Bounds box;
  for (int lane = 0; lane < count; ++lane) box.addBounds(laneBounds(lane));
  return box;
}

void BroadPhase::rebuild(std::span<const BroadPhaseItem> items) {
  nodes_.clear();
  nodeOfId_.clear();
  laneOfId_.clear();
  size_ = 0;
  std::vector<BroadPhaseItem> kept;
  for (const BroadPhaseItem& item : items)
    if (!item.bounds.isCleared()) kept.push_back(item);
  if (kept.empty()) return;
  EntityId maxId = 0;
  for (const BroadPhaseItem& item : kept) maxId = std::max(maxId, item.id);
  nodeOfId_.assign(std::size_t(maxId) + 1, -1);
  laneOfId_.assign(std::size_t(maxId) + 1, -1);
  size_ = kept.size();
  nodes_.reserve(kept.size() / 2 + 1);
  nodes_.emplace_back();
  build(kept, 0, 0, kept.size());
}

void BroadPhase::build(std::vector<BroadPhaseItem>& items, std::int32_t self, std::size_t begin,
                       std::size_t end) {
  // Four groups (fewer when there are at most four items: one each).
  std::size_t cuts[5] = {begin, end, end, end, end};
  int groups = 0;
  if (end - begin <= 4) {
    for (std::size_t k = begin; k <= end; ++k) cuts[groups++] = k;
    --groups;
  } else {
    const std::size_t mid = splitAtMedian(items, begin, end);
    cuts[0] = begin;
    cuts[1] = splitAtMedian(items, begin, mid);
    cuts[2] = mid;
    cuts[3] = splitAtMedian(items, mid, end);
    cuts[4] = end;
    groups = 4;
  }
  nodes_[std::size_t(self)].count = groups;
  for (int lane = 0; lane < groups; ++lane) {
    const std::size_t b = cuts[lane], e = cuts[lane + 1];
    if (e - b == 1) {
      const BroadPhaseItem& item = items[b];
      Node& node = nodes_[std::size_t(self)];
      node.child[lane] = ~item.id;
      node.setLane(lane, item.bounds);
      nodeOfId_[std::size_t(item.id)] = self;
      laneOfId_[std::size_t(item.id)] = lane;
      continue;
    }
    const auto child = std::int32_t(nodes_.size());
    nodes_.emplace_back();  // (references into nodes_ die here)
    nodes_[std::size_t(child)].parent = self;
    nodes_[std::size_t(child)].parentLane = lane;
    build(items, child, b, e);
    Node& node = nodes_[std::size_t(self)];
    node.child[lane] = child;
    node.setLane(lane, nodes_[std::size_t(child)].bounds());
  }
}

bool BroadPhase::refit(EntityId id, const Bounds& bounds) {
  if (id < 0 || std::size_t(id) >= nodeOfId_.size() || nodeOfId_[std::size_t(id)] < 0 || bounds.isCleared())
    return false;
  std::int32_t n = nodeOfId_[std::size_t(id)];
  nodes_[std::size_t(n)].setLane(laneOfId_[std::size_t(id)], bounds);
  for (; nodes_[std::size_t(n)].parent >= 0; n = nodes_[std::size_t(n)].parent) {
    const Node& node = nodes_[std::size_t(n)];
    nodes_[std::size_t(node.parent)].setLane(node.parentLane, node.bounds());
  }
  return true;
}

void BroadPhase::collectBox(const Bounds& box, std::vector<EntityId>& out) const {
  if (nodes_.empty()) return;
  // The next node is kept in a register: the first child node a node's test
  // passes is visited at once, the others wait on the stack (most queries
  // pass one child per level, or none).
  Walk walk;
  std::int32_t node = 0;
#ifdef CMKIT_FLOAT_LANES
  using simd::F4;
  const F4 qMinX = F4::all(box.min.x), qMinY = F4::all(box.min.y), qMinZ = F4::all(box.min.z);
  const F4 qMaxX = F4::all(box.max.x), qMaxY = F4::all(box.max.y), qMaxZ = F4::all(box.max.z);
#endif
  for (;;) {
    const Node& n = nodes_[std::size_t(node)];
#ifdef CMKIT_FLOAT_LANES
    // Bounds::intersects, four lanes at once: no axis where one box ends
    // before the other begins (the cleared lanes fail every axis).
    const F4 meets = (qMinX <= F4::load(n.maxX)) & (qMaxX >= F4::load(n.minX)) & (qMinY <= F4::load(n.maxY)) &
                     (qMaxY >= F4::load(n.minY)) & (qMinZ <= F4::load(n.maxZ)) & (qMaxZ >= F4::load(n.minZ));
    unsigned lanes = simd::bits(meets);
#else
    unsigned lanes = 0;
    for (int lane = 0; lane < n.count; ++lane) lanes |= unsigned(box.intersects(n.laneBounds(lane))) << lane;
#endif
    std::int32_t next = -1;
    for (; lanes != 0; lanes &= lanes - 1) {
      const std::int32_t child = n.child[std::countr_zero(lanes)];
      if (child < 0)
        out.push_back(~child);
      else if (next < 0)
        next = child;
      else
        walk.push(child);
    }
    if (next >= 0) {
      node = next;
    } else if (!walk.empty()) {
      node = walk.pop();
    } else {
      break;
    }
  }
}

}  // namespace cmkit::detail
