// The World: its entities, how a map places them, and the one writer's
// changes (add, remove, move). The queries are in world_queries.cpp, the
// batches in world_batch.cpp.
#include "cmkit/world.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <exception>
#include <new>

#include "query/query_guards.h"
#include "world/world_data.h"

namespace cmkit {

using detail::EntitySlot;
using detail::WorldData;

namespace detail {

Bounds placedBounds(const Bounds& local, const Placement& placement) {
  Bounds world;
  if (local.isCleared()) return world;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c{local[corner & 1].x, local[(corner >> 1) & 1].y, local[(corner >> 2) & 1].z};
    world.addPoint(placement.origin + c * placement.axis);
  }
  return world;
}

void EntitySlot::place(const Placement& placement) {
  entity.placement = placement;
  entity.bounds = placedBounds(entity.model->bounds(), placement);
  static_assert(sizeof(Placement) == 12 * sizeof(Real), "compared byte for byte: no padding");
  Placement guarded = placement;
  placementGuarded =
      guardPlacement(guarded) == QueryStatus::Ok && std::memcmp(&guarded, &placement, sizeof(Placement)) == 0;
}

void WorldData::rebuildTree() {
  std::vector<BroadPhaseItem> items;
  items.reserve(live);
  for (const auto& s : slots)
    if (s && s->entity.id != worldModel) items.push_back({s->entity.id, s->entity.bounds});
  tree.rebuild(items);
}

}  // namespace detail

namespace {

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
         });
}

Real largestMagnitude(const Bounds& b) {
  if (b.isCleared()) return 0;
  Real m = 0;
  for (int i = 0; i < 3; ++i) m = std::max({m, std::fabs(b.min[i]), std::fabs(b.max[i])});
  return m;
}

/// A placement checked as a query checks one: a finite origin within
/// tol::kMaxQueryCoordinate, an axis that is a rotation (re-orthonormalised
/// when it drifted, validateAxis).
Result<Placement> checkedPlacement(const Placement& p) {
  if (!p.origin.isFinite()) return Error("entity origin is not finite");
  for (int i = 0; i < 3; ++i)
    if (std::fabs(p.origin[i]) > tol::kMaxQueryCoordinate)
      return Error("entity origin lies beyond the largest query coordinate");
  Result<Mat3> axis = validateAxis(p.axis);
  if (!axis) return Error("entity axis: " + axis.error().message);
  return Placement{p.origin, *axis};
}

/// Adds an entity (placement already checked) to the slots; the caller
/// rebuilds the tree.
EntityId addSlot(WorldData& d, WorldEntity e) {
  e.id = EntityId(d.slots.size());
  auto slot = std::make_unique<EntitySlot>();
  std::weak_ptr<const RayIndex>& cached = d.rayIndexes[e.model.get()];
  slot->rays = cached.lock();
  if (!slot->rays) {
    slot->rays = std::make_shared<const RayIndex>(*e.model);
    cached = slot->rays;
  }
  d.maxLocalMagnitude = std::max(d.maxLocalMagnitude, largestMagnitude(e.model->bounds()));
  const Placement placement = e.placement;
  slot->entity = std::move(e);
  slot->place(placement);
  d.slots.push_back(std::move(slot));
  ++d.live;
  return EntityId(d.slots.size() - 1);
}

EntitySlot* liveSlot(WorldData& d, EntityId id) {
  return id >= 0 && std::size_t(id) < d.slots.size() ? d.slots[std::size_t(id)].get() : nullptr;
}

Error noEntity(EntityId id) { return Error("no entity with id " + std::to_string(id)); }

}  // namespace

std::optional<std::string_view> WorldEntity::value(std::string_view key) const {
  for (const auto& [k, v] : keyValues)
    if (equalsIgnoreCase(k, key)) return std::string_view(v);
  return std::nullopt;
}

World::World() : data_(std::make_unique<WorldData>()) {}
World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

Result<LoadedWorld> World::loadMap(const std::string& mapPath, const MaterialTable& materials,
                                   const LoadMapOptions& options) {
  // The manager makes the models as a game's loader does (NAME.cm or a
  // build, .proc pruning); the map is read again here for its entities.
  ModelManager manager;
  Result<LoadMapResult> loaded = manager.loadMap(mapPath, materials, options);
  if (!loaded) return loaded.error();
  Result<MapFile> map = loadMapFile(mapPath);
  if (!map) return map.error();
  std::vector<ModelPtr> models;
  for (const ModelHandle h : loaded->handles) models.push_back(manager.get(h));
  Result<LoadedWorld> world = fromMap(*map, models);
  if (!world) return world.error();
  world->report.models = std::move(loaded).value();
  return world;
}

namespace {

/// A func_group entity: an editor's group of world brushes. Tools that merge
/// them into the world model (RBDoom-3-BFG's, for TrenchBroom maps) write
/// no model of their own for them.
bool isFuncGroup(const MapEntity& e) {
  return e.value("classname") == std::optional<std::string_view>("func_group");
}

}  // namespace

Result<LoadedWorld> World::fromMap(const MapFile& map, std::span<const ModelPtr> models) {
  try {
    std::size_t owners = 0, groups = 0;
    for (std::size_t i = 0; i < map.entities.size(); ++i) {
      const MapEntity& e = map.entities[i];
      owners += !e.primitives.empty();
      groups += i != 0 && !e.primitives.empty() && isFuncGroup(e);
    }
    // One model per entity with primitives (cmkit's build, the original's);
    // or none for func_groups, whose primitives are in the world model.
    const bool groupsInWorld = owners != models.size() && groups > 0 && owners - groups == models.size();
    if (owners != models.size() && !groupsInWorld)
      return Error("the map has " + std::to_string(owners) + " entities with brushes or patches (" +
                       std::to_string(groups) + " of them func_group) but " + std::to_string(models.size()) +
                       " models were given (one per such entity, in map order, or one per such entity "
                       "but the func_groups)",
                   map.fileName);
    LoadedWorld out;
    WorldData& d = *out.world.data_;
    std::size_t next = 0;
    for (std::size_t i = 0; i < map.entities.size(); ++i) {
      const MapEntity& e = map.entities[i];
      if (e.primitives.empty()) {
        // A `model` key without primitives names a mesh file: not placed.
        if (i != 0 && e.value("model")) ++out.report.meshModelsSkipped;
        continue;
      }
      if (groupsInWorld && i != 0 && isFuncGroup(e)) {
        ++out.report.funcGroupsInWorld;
        continue;
      }
      const ModelPtr& model = models[next++];
      if (!model) return Error("model " + std::to_string(next - 1) + " is null", map.fileName);
      const bool world = i == 0;
      if (!world && e.value("noclipmodel") == std::optional<std::string_view>("1")) {
        ++out.report.noclipSkipped;
        continue;
      }
      WorldEntity we;
      if (world) {
        we.name = "worldspawn";
      } else if (auto name = e.value("name")) {
        we.name = std::string(*name);
      } else {
        we.name = "#" + std::to_string(i);
      }
      if (auto cls = e.value("classname")) we.className = std::string(*cls);
      we.keyValues = e.keyValues;
      we.model = model;
      we.contents = model->contents();
      we.mapEntity = std::int32_t(i);
      if (!world) {
        // The engine's placement: `origin`, and `rotation` or else `angle`
        // (MapEntity::axis).
        Result<Placement> placement = checkedPlacement({e.origin(), e.axis()});
        if (!placement)
          return Error("entity " + std::to_string(i) + " (" + we.name + "): " + placement.error().message,
                       map.fileName, e.line);
        we.placement = *placement;
      }
      const EntityId id = addSlot(d, std::move(we));
      if (world) d.worldModel = id;
    }
    d.rebuildTree();
    out.report.entitiesPlaced = int(d.live);
    return out;
  } catch (const std::bad_alloc&) {
    return Error("out of memory while placing the map's entities", map.fileName);
  }
}

Result<EntityId> World::addEntity(EntityDesc desc) {
  if (!desc.model) return Error("addEntity: no model");
  Result<Placement> placement = checkedPlacement(desc.placement);
  if (!placement) return Error("addEntity: " + placement.error().message);
  WorldEntity e;
  e.name = std::move(desc.name);
  e.className = std::move(desc.className);
  e.keyValues = std::move(desc.keyValues);
  e.contents = desc.contents.value_or(desc.model->contents());
  e.model = std::move(desc.model);
  e.placement = *placement;
  const EntityId id = addSlot(*data_, std::move(e));
  data_->rebuildTree();
  return id;
}

Result<EntityId> World::addTraceModelEntity(std::string name, const TraceModel& trm,
                                            const Placement& placement, std::uint32_t contents) {
  EntityDesc desc;
  desc.name = std::move(name);
  desc.className = "tracemodel";
  desc.model = collisionModelFromTraceModel(trm, contents);
  desc.placement = placement;
  desc.contents = contents;
  return addEntity(std::move(desc));
}

Status World::removeEntity(EntityId id) {
  EntitySlot* slot = liveSlot(*data_, id);
  if (!slot) return noEntity(id);
  const CollisionModel* model = slot->entity.model.get();
  data_->slots[std::size_t(id)].reset();
  --data_->live;
  if (auto it = data_->rayIndexes.find(model); it != data_->rayIndexes.end() && it->second.expired())
    data_->rayIndexes.erase(it);
  if (id == data_->worldModel)
    data_->worldModel = kNoEntity;
  else
    data_->rebuildTree();
  return Ok{};
}

Status World::setPlacement(EntityId id, const Placement& placement) {
  EntitySlot* slot = liveSlot(*data_, id);
  if (!slot) return noEntity(id);
  Result<Placement> checked = checkedPlacement(placement);
  if (!checked) return Error("setPlacement: " + checked.error().message);
  slot->place(*checked);
  if (id != data_->worldModel && !data_->tree.refit(id, slot->entity.bounds)) data_->rebuildTree();
  return Ok{};
}

Status World::setContents(EntityId id, std::uint32_t contents) {
  EntitySlot* slot = liveSlot(*data_, id);
  if (!slot) return noEntity(id);
  slot->entity.contents = contents;
  return Ok{};
}

const WorldEntity* World::entity(EntityId id) const {
  const EntitySlot* s = data_->slot(id);
  return s ? &s->entity : nullptr;
}

EntityId World::find(std::string_view name) const {
  for (const auto& s : data_->slots)
    if (s && s->entity.name == name) return s->entity.id;
  return kNoEntity;
}

std::vector<EntityId> World::entityIds() const {
  std::vector<EntityId> ids;
  ids.reserve(data_->live);
  for (const auto& s : data_->slots)
    if (s) ids.push_back(s->entity.id);
  return ids;
}

std::size_t World::size() const { return data_->live; }

EntityId World::idLimit() const { return EntityId(data_->slots.size()); }

WorldQueryWork::WorldQueryWork() : scratch_(std::make_unique<detail::WorldScratch>()) {}
WorldQueryWork::~WorldQueryWork() = default;
WorldQueryWork::WorldQueryWork(WorldQueryWork&&) noexcept = default;
WorldQueryWork& WorldQueryWork::operator=(WorldQueryWork&&) noexcept = default;
QueryWork& WorldQueryWork::modelWork() { return scratch_->model; }

}  // namespace cmkit
