// The audit's spots (audit.h): which map entities are player starts,
// monsters, items and movers, and the position test of each spot.
#include <algorithm>
#include <cctype>

#include "audit/audit_impl.h"
#include "cmkit/tolerances.h"

namespace cmkit {

namespace {

/// The class name after any "prefix:", in lower case.
std::string bareClass(std::string_view className) {
  const std::size_t colon = className.rfind(':');
  if (colon != std::string_view::npos) className = className.substr(colon + 1);
  std::string out(className);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return out;
}

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

/// A monster's box: the original's usual 32 x 32 footprint, 64 high, its
/// origin at the feet.
constexpr Real kMonsterHalfWidth = 16;
constexpr Real kMonsterHeight = 64;
/// An item's cube: 12 units wide, centred on the item's origin.
constexpr Real kItemHalfWidth = 6;

}  // namespace

std::string_view toString(AuditKind kind) {
  switch (kind) {
    case AuditKind::FallOut:
      return "fallout";
    case AuditKind::Stuck:
      return "stuck";
    case AuditKind::Tunnel:
      return "tunnel";
    case AuditKind::Embedded:
      return "embedded";
    case AuditKind::OpenShell:
      return "open_shell";
  }
  return "?";
}

std::string_view toString(AuditSeverity severity) {
  switch (severity) {
    case AuditSeverity::Low:
      return "low";
    case AuditSeverity::Medium:
      return "medium";
    case AuditSeverity::High:
      return "high";
  }
  return "?";
}

bool isMoverClass(std::string_view className) {
  const std::string c = bareClass(className);
  for (std::string_view p : {"func_door", "func_mover", "func_plat", "func_rotating", "func_elevator",
                             "func_pendulum", "func_bobbing", "func_moveable", "moveable_", "mover_"})
    if (startsWith(c, p)) return true;
  return c.find("door") != std::string::npos;
}

bool isTriggerClass(std::string_view className) { return startsWith(bareClass(className), "trigger_"); }

std::vector<AuditSpot> auditSpotsFromMap(const MapFile& map) {
  std::vector<AuditSpot> out;
  for (std::size_t i = 0; i < map.entities.size(); ++i) {
    const MapEntity& e = map.entities[i];
    const std::string_view className = e.value("classname").value_or("");
    const std::string c = bareClass(className);
    AuditSpot spot;
    if (c == "info_player_start") {
      spot.kind = AuditSpotKind::PlayerStart;
    } else if (startsWith(c, "monster_") || startsWith(c, "ai_")) {
      spot.kind = AuditSpotKind::Monster;
    } else if (startsWith(c, "item_") || startsWith(c, "weapon_") || startsWith(c, "ammo_") ||
               startsWith(c, "moveable_") || startsWith(c, "playertools_") || startsWith(c, "key_")) {
      spot.kind = AuditSpotKind::Item;
    } else {
      continue;
    }
    if (!e.value("origin")) continue;
    spot.origin = e.origin();
    spot.name = std::string(e.value("name").value_or(""));
    if (spot.name.empty()) spot.name = "#" + std::to_string(i);
    spot.className = std::string(className);
    spot.mapEntity = std::int32_t(i);
    out.push_back(std::move(spot));
  }
  return out;
}

namespace audit_detail {

std::vector<RawFinding> findEmbedded(const World& world, std::span<const AuditSpot> spots) {
  std::vector<RawFinding> out;
  WorldQueryWork work;
  const PlayerShape player = PlayerShape::standard();
  const auto monster = TraceModel::box(
      {{-kMonsterHalfWidth, -kMonsterHalfWidth, 0}, {kMonsterHalfWidth, kMonsterHalfWidth, kMonsterHeight}});
  const auto item = TraceModel::box({{-kItemHalfWidth, -kItemHalfWidth, -kItemHalfWidth},
                                     {kItemHalfWidth, kItemHalfWidth, kItemHalfWidth}});
  for (const AuditSpot& spot : spots) {
    // The spot's own entity (when it has a model in the world) is left out.
    std::vector<EntityId> self;
    for (EntityId id : world.entityIds())
      if (world.entity(id)->mapEntity == spot.mapEntity) self.push_back(id);
    EntityFilter filter;
    filter.ignore = self;
    ContentsQuery q;
    q.contentMask = contents::kMaskSolid;
    AuditSeverity severity = AuditSeverity::Low;
    switch (spot.kind) {
      case AuditSpotKind::PlayerStart:
        q.trm = &player.standing;
        q.contentMask = player.contentMask;
        severity = AuditSeverity::High;
        break;
      case AuditSpotKind::Monster:
        q.trm = monster ? &*monster : nullptr;
        severity = AuditSeverity::Medium;
        break;
      case AuditSpotKind::Item:
        q.trm = item ? &*item : nullptr;
        break;
    }
    // As the player's start in solid: lifted by up to kPlayerMaxNudge (a
    // spot put on the floor, or a little into it, is not embedded).
    bool free = false;
    WorldContentsResult first;
    for (Real lift = 0; lift <= tol::kPlayerMaxNudge && !free; lift += tol::kPlayerNudgeStep) {
      q.position = spot.origin + Vec3{0, 0, lift};
      const WorldContentsResult r = world.contentsTest(q, work, filter);
      if (lift == 0) first = r;
      free = r.result.contents == 0;
    }
    if (free) continue;
    const WorldEntity* in = world.entity(first.entity);
    const char* what = spot.kind == AuditSpotKind::PlayerStart ? "player start"
                       : spot.kind == AuditSpotKind::Monster   ? "monster"
                                                               : "item";
    std::string text = std::string(what) + " \"" + spot.name + "\" (" + spot.className + ") is in solid";
    if (in) text += " of entity " + std::to_string(in->id) + " \"" + in->name + "\"";
    out.push_back({AuditKind::Embedded, severity, spot.origin, std::move(text), -1});
  }
  return out;
}

}  // namespace audit_detail

}  // namespace cmkit
