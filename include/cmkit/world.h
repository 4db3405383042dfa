// world.h: a world of placed collision models (a map's world model and its
// entities' models, trace-model "monsters", models of the caller's), queried
// as one.
//
// CONTRACT
// - A World holds ENTITIES. Each has a stable id (EntityId, never reused
//   while the world lives), a name, a class name, its key/values, a sealed
//   model (ModelPtr, shared, never written), its contents and a placement
//   (origin + axis: world = origin + local * axis, as Placement everywhere).
// - From a map (World::loadMap, World::fromMap): entity 0 is the world model,
//   named "worldspawn", placed at the origin; then, in map order, every other
//   entity that owns brushes or patches, its model built in the entity's
//   LOCAL frame and placed by its keys: `origin`, and `rotation` (nine
//   numbers, the axis rows) or else `angle` (a yaw in degrees about +z;
//   `rotation` wins). Not placed: entities with `noclipmodel` "1", and
//   entities whose `model` key names a file (a mesh; they own no primitives)
//   - LoadedWorld::report counts both. A .cm written by tools that merge
//   func_group entities into the world model has no model for them: such
//   entities are left out too (report.funcGroupsInWorld). docs/world.md
//   says it all.
// - An entity's `contents` is what it can collide as: a query whose content
//   mask does not meet it skips the entity (the model's own polygon and brush
//   contents still decide each hit). It starts as the model's contents();
//   setContents(id, 0) makes an entity non-colliding.
// - QUERIES take the single-model query structs of query.h / ray_index.h;
//   their `placement` field is IGNORED (each entity has its own). A query
//   asks every entity whose placed bounds its sweep touches (a broad phase:
//   an AABB tree over the entities' world bounds; the world model, entity
//   0 of a map, is always asked) and keeps:
//     translate, rotate: the smallest fraction; equal fractions: the LOWEST
//       entity id. A miss (fraction 1) has entity kNoEntity. startSolid is
//       the OR over the entities asked.
//     contentsTest: contents = the OR of every entity's contents result;
//       trace and entity: the lowest-id entity overlapped.
//     pointContents: the OR over the entities; entity: the lowest id with
//       contents.
//     contacts: every entity's contacts, each with its entity, in entity-id
//       order (rotational contacts: by |angle|, then entity id, then each
//       model's order), at most maxContacts in all.
//     castRay: the smallest crossing fraction; ties: the lowest entity id.
//   So a world answer is the closest of the per-entity answers that a loop
//   over all entities would give (tests/unit/test_world_queries.cpp checks
//   it by brute force).
// - EntityFilter leaves entities out: an ignore list and/or a callback.
// THREAD SAFETY
// - Query functions are const and keep no state: any number of threads may
//   query one World at once, each with its own WorldQueryWork.
// - Mutators (addEntity, removeEntity, setPlacement, setContents) need
//   exclusive access: ONE writer, run between queries, never concurrently
//   with a query or another mutator (no lock is taken; the caller orders
//   them, e.g. a game's tick: move, then query).
// - Batches (the *Batch functions below) are loops of the single world
//   queries on BatchOptions::threads workers: out[i] is, bit for bit, the
//   single query's answer at any thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/manager.h"
#include "cmkit/map.h"
#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/result.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// An entity's id in a World: stable while the world lives, never reused.
using EntityId = std::int32_t;
/// No entity (a miss).
inline constexpr EntityId kNoEntity = -1;
/// The world model's id in a world made from a map.
inline constexpr EntityId kWorldspawnEntity = 0;

/// An entity of a World, as the world holds it (read-only to callers).
struct WorldEntity {
  EntityId id = kNoEntity;  ///< its id
  std::string name;         ///< `name` key; "worldspawn"; "#N" (map entity N) without one
  std::string className;    ///< `classname` key ("" when none)
  /// The entity's key/values (of the map, or the caller's).
  std::vector<std::pair<std::string, std::string>> keyValues;
  ModelPtr model;               ///< the model, in the entity's local frame
  Placement placement;          ///< where the model is (world = origin + local * axis)
  std::uint32_t contents = 0;   ///< what it collides as (see the contract)
  Bounds bounds;                ///< world bounds of the placed model
  std::int32_t mapEntity = -1;  ///< index into the map's entities; -1: added by the caller

  /// The value of a key (case-insensitive, as MapEntity::value), or nullopt.
  std::optional<std::string_view> value(std::string_view key) const;
};

/// What addEntity adds: every field of WorldEntity a caller chooses.
struct EntityDesc {
  std::string name;                                            ///< the entity's name (need not be unique)
  std::string className;                                       ///< free text ("" allowed)
  std::vector<std::pair<std::string, std::string>> keyValues;  ///< kept as given
  ModelPtr model;                                              ///< must not be null
  Placement placement;                                         ///< axis must be a rotation
  /// What it collides as; nullopt: the model's contents().
  std::optional<std::uint32_t> contents;
};

/// Entities a query leaves out.
struct EntityFilter {
  /// Entities never asked (any order; ids of removed entities are ignored).
  std::span<const EntityId> ignore;
  /// Asked for each entity the broad phase finds (after `ignore`); false
  /// leaves it out. Empty: every entity. Called on the querying thread (a
  /// batch's workers call it at once: it must be safe to); it must not
  /// change the world.
  std::function<bool(const WorldEntity&)> accept;
};

/// A translation's or rotation's answer: the closest entity's trace.
struct WorldTraceResult {
  TraceResult trace;            ///< the closest answer (see the contract)
  EntityId entity = kNoEntity;  ///< the entity hit; kNoEntity on a miss
};

/// A position test's answer.
struct WorldContentsResult {
  /// contents: the OR over entities; trace: that of `entity`.
  ContentsResult result;
  EntityId entity = kNoEntity;  ///< the lowest-id entity overlapped; kNoEntity: free
};

/// Point contents over the world.
struct WorldPointContentsResult {
  std::uint32_t contents = 0;            ///< the OR over entities
  EntityId entity = kNoEntity;           ///< the lowest id with contents; kNoEntity: none
  QueryStatus status = QueryStatus::Ok;  ///< refused: contents 0
};

/// One contact with the entity it belongs to.
struct WorldContact {
  ContactInfo contact;          ///< as contacts() reports it (world space)
  EntityId entity = kNoEntity;  ///< whose model was touched
};

/// The contacts of a query over the world.
struct WorldContactsResult {
  std::vector<WorldContact> contacts;    ///< ordered as the contract says
  QueryStatus status = QueryStatus::Ok;  ///< refused: no contacts
};

/// A ray's answer over the world.
struct WorldRayHit {
  RayHit hit;                   ///< the first crossing (polygon of `entity`'s model)
  EntityId entity = kNoEntity;  ///< kNoEntity on a miss
};

namespace detail {
struct WorldData;
struct WorldScratch;
struct WorldWorkAccess;
}  // namespace detail

/// Caller-owned scratch of world queries (one per thread, reusable): a
/// QueryWork and the broad phase's candidate list.
class WorldQueryWork {
 public:
  WorldQueryWork();
  ~WorldQueryWork();
  /// Moves the scratch.
  WorldQueryWork(WorldQueryWork&&) noexcept;
  /// Moves the scratch.
  WorldQueryWork& operator=(WorldQueryWork&&) noexcept;
  WorldQueryWork(const WorldQueryWork&) = delete;
  WorldQueryWork& operator=(const WorldQueryWork&) = delete;

  /// The per-model scratch (its work counters sum every entity asked).
  QueryWork& modelWork();

 private:
  friend struct detail::WorldWorkAccess;
  std::unique_ptr<detail::WorldScratch> scratch_;
};

class World;

/// What loading a map into a World did.
struct WorldLoadReport {
  /// loadMap: how the models were made (.cm or built, .proc, warnings);
  /// fromMap: left empty.
  LoadMapResult models;
  int entitiesPlaced = 0;     ///< entities in the world, worldspawn included
  int noclipSkipped = 0;      ///< entities with primitives left out for `noclipmodel` "1"
  int meshModelsSkipped = 0;  ///< entities without primitives whose `model` key names a file
  /// func_group entities given no model of their own: the models (a .cm
  /// written by tools that merge func_groups into the world, such as
  /// RBDoom-3-BFG's) hold their primitives in the world model.
  int funcGroupsInWorld = 0;
};

/// A world loaded from a map, with its report.
struct LoadedWorld;

/// A world of placed collision models. See the file comment.
class World {
 public:
  /// An empty world (no world model; entities added by the caller).
  World();
  ~World();
  /// Moves the world (entity ids stay). A moved-from World may only be
  /// destroyed or assigned to.
  World(World&&) noexcept;
  /// Moves the world (entity ids stay).
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Loads a .map: its models as ModelManager::loadMap makes them (NAME.cm
  /// beside it when its CRC matches, else built; the world pruned by
  /// NAME.proc), placed by the map's entity keys.
  static Result<LoadedWorld> loadMap(const std::string& mapPath, const MaterialTable& materials,
                                     const LoadMapOptions& options = {});
  /// A world from a parsed map and its models (buildCollisionModels' output,
  /// or a .cm file's models for that map): models[k] belongs to the k-th
  /// entity that owns primitives. Error when the counts differ.
  static Result<LoadedWorld> fromMap(const MapFile& map, std::span<const ModelPtr> models);

  /// Adds an entity; returns its id. Error: no model, or an axis that is not
  /// a rotation. Writer only.
  Result<EntityId> addEntity(EntityDesc desc);
  /// Adds the model of a trace model (collisionModelFromTraceModel), e.g. a
  /// box or cylinder for a monster or player, placed at `placement`.
  Result<EntityId> addTraceModelEntity(std::string name, const TraceModel& trm, const Placement& placement,
                                       std::uint32_t contents = contents::kSolid);
  /// Removes an entity (its id is not reused). Error: no such entity. Writer only.
  Status removeEntity(EntityId id);
  /// Moves an entity. Error: no such entity, an axis that is not a
  /// rotation. Writer only.
  Status setPlacement(EntityId id, const Placement& placement);
  /// Sets what an entity collides as (0: nothing). Writer only.
  Status setContents(EntityId id, std::uint32_t contents);

  /// The entity, or nullptr (never added, or removed).
  const WorldEntity* entity(EntityId id) const;
  /// The first live entity (lowest id) named exactly `name`, or kNoEntity.
  EntityId find(std::string_view name) const;
  /// Ids of the live entities, ascending.
  std::vector<EntityId> entityIds() const;
  /// Number of live entities.
  std::size_t size() const;
  /// One past the largest id ever given.
  EntityId idLimit() const;

  /// Moves a trace model through the world (TranslationQuery; its
  /// placement is ignored).
  WorldTraceResult translate(const TranslationQuery& query, WorldQueryWork& work,
                             const EntityFilter& filter = {}) const;
  /// Rotates a trace model through the world.
  WorldTraceResult rotate(const RotationQuery& query, WorldQueryWork& work,
                          const EntityFilter& filter = {}) const;
  /// What a placed trace model overlaps in the world.
  WorldContentsResult contentsTest(const ContentsQuery& query, WorldQueryWork& work,
                                   const EntityFilter& filter = {}) const;
  /// Contents of the brushes containing a point, over the world (no mask:
  /// entities of contents 0 are skipped).
  WorldPointContentsResult pointContents(const PointContentsQuery& query, WorldQueryWork& work,
                                         const EntityFilter& filter = {}) const;
  /// Every contact of a move or turn, each with its entity.
  WorldContactsResult contacts(const ContactsQuery& query, WorldQueryWork& work,
                               const EntityFilter& filter = {}) const;
  /// The first front face a segment crosses, over the world (each entity's
  /// RayIndex, made when the entity's model first entered the world).
  WorldRayHit castRay(const RayCastQuery& query, WorldQueryWork& work, const EntityFilter& filter = {}) const;

 private:
  std::unique_ptr<detail::WorldData> data_;
};

/// A world loaded from a map, with its report (World::loadMap, World::fromMap).
struct LoadedWorld {
  World world;             ///< the world
  WorldLoadReport report;  ///< what was placed and skipped
};

/// out[i] = world.translate(query i) (TranslationBatch: batch.h).
Status translateBatch(const World& world, const TranslationBatch& batch, std::span<WorldTraceResult> out,
                      const BatchOptions& options = {}, const EntityFilter& filter = {});
/// out[i] = world.rotate(query i).
Status rotateBatch(const World& world, const RotationBatch& batch, std::span<WorldTraceResult> out,
                   const BatchOptions& options = {}, const EntityFilter& filter = {});
/// out[i] = world.contentsTest(query i).
Status contentsBatch(const World& world, const ContentsBatch& batch, std::span<WorldContentsResult> out,
                     const BatchOptions& options = {}, const EntityFilter& filter = {});
/// out[i] = world.pointContents(query i).
Status pointContentsBatch(const World& world, const PointContentsBatch& batch,
                          std::span<WorldPointContentsResult> out, const BatchOptions& options = {},
                          const EntityFilter& filter = {});
/// out[i] = world.contacts(query i).
Status contactsBatch(const World& world, const ContactsBatch& batch, std::span<WorldContactsResult> out,
                     const BatchOptions& options = {}, const EntityFilter& filter = {});
/// out[i] = world.castRay(ray i) (RayBatch: ray_index.h; its placement ignored).
Status castRayBatch(const World& world, const RayBatch& batch, std::span<WorldRayHit> out,
                    const BatchOptions& options = {}, const EntityFilter& filter = {});

}  // namespace cmkit
