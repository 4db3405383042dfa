// world_data.h: what a World holds (its entities, the broad phase, the
// shared ray indexes) and what a WorldQueryWork holds. Private to src/world.
#pragma once

#include <memory>
#include <unordered_map>
#include <vector>

#include "cmkit/ray_index.h"
#include "cmkit/world.h"
#include "world/broad_phase.h"

namespace cmkit::detail {

/// An entity and what the world keeps beside it.
struct EntitySlot {
  WorldEntity entity;
  /// The ray index of entity.model, shared by every entity of that model.
  std::shared_ptr<const RayIndex> rays;
  /// The queries' guard accepts entity.placement and leaves it as it is
  /// (guardPlacement; set with the placement): the world asks this entity
  /// with the guarded queries (query_guards.h) on input it checked once.
  bool placementGuarded = false;

  /// Sets entity.placement, its world bounds and placementGuarded.
  void place(const Placement& placement);
};

/// A World's state. Written only by the World's mutators (one writer).
struct WorldData {
  /// By id; null: removed. Ids are never reused.
  std::vector<std::unique_ptr<EntitySlot>> slots;
  std::size_t live = 0;
  /// The world model (asked by every query, outside the tree), or kNoEntity.
  EntityId worldModel = kNoEntity;
  /// Every other live entity.
  BroadPhase tree;
  /// Ray indexes by model, shared while an entity of that model lives.
  std::unordered_map<const CollisionModel*, std::weak_ptr<const RayIndex>> rayIndexes;
  /// The largest coordinate magnitude of any model's local bounds added so
  /// far (never shrinks): how far the ray broad phase pads (RayIndex's
  /// acceptance padding is relative to it).
  Real maxLocalMagnitude = 0;

  const EntitySlot* slot(EntityId id) const {
    return id >= 0 && std::size_t(id) < slots.size() ? slots[std::size_t(id)].get() : nullptr;
  }
  /// Rebuilds the tree over every live entity but the world model.
  void rebuildTree();
};

/// The world bounds of a box of the model's frame placed by `placement`
/// (the box around its eight placed corners; cleared stays cleared).
Bounds placedBounds(const Bounds& local, const Placement& placement);

/// A WorldQueryWork's contents.
struct WorldScratch {
  QueryWork model;                    ///< for the per-entity queries
  std::vector<EntityId> candidates;   ///< the broad phase's answer
  std::vector<ContactInfo> contacts;  ///< one entity's contacts
};

/// How world functions reach a WorldQueryWork's scratch.
struct WorldWorkAccess {
  static WorldScratch& of(WorldQueryWork& work) { return *work.scratch_; }
};

}  // namespace cmkit::detail
