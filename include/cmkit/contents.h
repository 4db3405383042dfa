// contents.h: content flags of surfaces and volumes (solid, water, clip...).
//
// The bit values are the original engine's: they appear as integers in query
// results and as names in .cm brush records.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "cmkit/result.h"

namespace cmkit {

/// Content flags. Values are bit masks; combine with |.
namespace contents {
/// Content flag: solid: blocks movement.
inline constexpr std::uint32_t kSolid = 1u << 0;
/// Content flag: opaque: blocks sight.
inline constexpr std::uint32_t kOpaque = 1u << 1;
/// Content flag: water.
inline constexpr std::uint32_t kWater = 1u << 2;
/// Content flag: player clip.
inline constexpr std::uint32_t kPlayerClip = 1u << 3;
/// Content flag: monster clip.
inline constexpr std::uint32_t kMonsterClip = 1u << 4;
/// Content flag: moveable clip.
inline constexpr std::uint32_t kMoveableClip = 1u << 5;
/// Content flag: inverse-kinematics clip.
inline constexpr std::uint32_t kIkClip = 1u << 6;
/// Content flag: blood (hit by blood decals).
inline constexpr std::uint32_t kBlood = 1u << 7;
/// Content flag: an actor's body.
inline constexpr std::uint32_t kBody = 1u << 8;
/// Content flag: a projectile.
inline constexpr std::uint32_t kProjectile = 1u << 9;
/// Content flag: a corpse.
inline constexpr std::uint32_t kCorpse = 1u << 10;
/// Content flag: a render model (shots against render models).
inline constexpr std::uint32_t kRenderModel = 1u << 11;
/// Content flag: a trigger volume.
inline constexpr std::uint32_t kTrigger = 1u << 12;
/// Content flag: solid for the AAS (AI navigation) compiler.
inline constexpr std::uint32_t kAasSolid = 1u << 13;
/// Content flag: an obstacle for the AAS compiler.
inline constexpr std::uint32_t kAasObstacle = 1u << 14;
/// Content flag: triggered by a flashlight.
inline constexpr std::uint32_t kFlashlightTrigger = 1u << 15;
/// Compile-time only: never reaches a collision model.
inline constexpr std::uint32_t kAreaPortal = 1u << 20;
/// Compile-time only: never reaches a collision model.
inline constexpr std::uint32_t kNoCsg = 1u << 21;

// Common masks.
/// Every flag.
inline constexpr std::uint32_t kMaskAll = 0xFFFFFFFFu;
/// What blocks ordinary traces: solid.
inline constexpr std::uint32_t kMaskSolid = kSolid;
/// What blocks a player: solid, player clip, bodies.
inline constexpr std::uint32_t kMaskPlayerSolid = kSolid | kPlayerClip | kBody;
/// What blocks a dead player: solid, player clip.
inline constexpr std::uint32_t kMaskDeadSolid = kSolid | kPlayerClip;
/// What blocks a monster: solid, monster clip, bodies.
inline constexpr std::uint32_t kMaskMonsterSolid = kSolid | kMonsterClip | kBody;
/// Water.
inline constexpr std::uint32_t kMaskWater = kWater;
/// What blocks sight: opaque.
inline constexpr std::uint32_t kMaskOpaque = kOpaque;
/// What shots against render models hit: solid, render models.
inline constexpr std::uint32_t kMaskShotRenderModel = kSolid | kRenderModel;
/// What shots against bounding boxes hit: solid, bodies.
inline constexpr std::uint32_t kMaskShotBoundingBox = kSolid | kBody;
}  // namespace contents

/// One named content flag.
struct ContentName {
  /// The flag's name as in .cm files and query results.
  std::string_view name;
  /// The flag's bit.
  std::uint32_t flag;
};

/// All named flags in bit order: solid, opaque, water, playerclip,
/// monsterclip, moveableclip, ikclip, blood, body, projectile, corpse,
/// renderModel, trigger, aas_solid, aas_obstacle, flashlight_trigger.
std::span<const ContentName> contentNames();

/// Parses comma-separated flag names ("solid,playerclip"); names are
/// case-sensitive as in the original, spaces around names are ignored, and an
/// empty string gives 0. An unknown name is an error quoting it.
Result<std::uint32_t> contentsFromString(std::string_view text);

/// Comma-separated names of the named flags set in `flags`, in bit order
/// ("" for 0). Unnamed bits are not listed: see contentsToStringExact.
std::string contentsToString(std::uint32_t flags);

/// As contentsToString, but bits without a name are appended as one
/// hexadecimal number ("solid,0x100000"), so nothing is lost.
std::string contentsToStringExact(std::uint32_t flags);

/// Parses a mask the way the query format writes it: comma-separated names,
/// or an integer in decimal (negative: two's complement, -1 = all) or 0x hex.
Result<std::uint32_t> parseContentsMask(std::string_view text);

}  // namespace cmkit
