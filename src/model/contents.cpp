// Content flag names: ContentsFromString / StringFromContents.
#include "cmkit/contents.h"

#include <array>
#include <charconv>
#include <cstdint>
#include <cstdio>

namespace cmkit {
namespace {

constexpr std::array<ContentName, 16> kNames{{
    {"solid", contents::kSolid},
    {"opaque", contents::kOpaque},
    {"water", contents::kWater},
    {"playerclip", contents::kPlayerClip},
    {"monsterclip", contents::kMonsterClip},
    {"moveableclip", contents::kMoveableClip},
    {"ikclip", contents::kIkClip},
    {"blood", contents::kBlood},
    {"body", contents::kBody},
    {"projectile", contents::kProjectile},
    {"corpse", contents::kCorpse},
    {"renderModel", contents::kRenderModel},
    {"trigger", contents::kTrigger},
    {"aas_solid", contents::kAasSolid},
    {"aas_obstacle", contents::kAasObstacle},
    {"flashlight_trigger", contents::kFlashlightTrigger},
}};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

}  // namespace

std::span<const ContentName> contentNames() { return kNames; }

Result<std::uint32_t> contentsFromString(std::string_view text) {
  std::uint32_t flags = 0;
  if (trim(text).empty()) return flags;
  size_t pos = 0;
  while (pos <= text.size()) {
    const size_t comma = text.find(',', pos);
    const std::string_view name =
        trim(text.substr(pos, comma == std::string_view::npos ? text.npos : comma - pos));
    bool found = false;
    for (const ContentName& n : kNames) {
      if (n.name == name) {
        flags |= n.flag;
        found = true;
        break;
      }
    }
    if (!found) {
      return Error{"unknown content name '" + std::string(name) +
                   "' (known: solid, opaque, water, "
                   "playerclip, monsterclip, moveableclip, ikclip, blood, body, projectile, corpse, "
                   "renderModel, trigger, aas_solid, aas_obstacle, flashlight_trigger)"};
    }
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  return flags;
}

std::string contentsToString(std::uint32_t flags) {
  std::string s;
  for (const ContentName& n : kNames) {
    if (flags & n.flag) {
      if (!s.empty()) s += ',';
      s += n.name;
    }
  }
  return s;
}

std::string contentsToStringExact(std::uint32_t flags) {
  std::string s = contentsToString(flags);
  std::uint32_t named = 0;
  for (const ContentName& n : kNames) named |= n.flag;
  if (const std::uint32_t rest = flags & ~named) {
    char buf[16];
    std::snprintf(buf, sizeof buf, "0x%x", rest);
    if (!s.empty()) s += ',';
    s += buf;
  }
  return s;
}

Result<std::uint32_t> parseContentsMask(std::string_view text) {
  const std::string_view t = trim(text);
  if (!t.empty() && t.front() == '-') {
    // A negative decimal is taken as its 32-bit two's complement (-1 = all).
    std::int64_t value = 0;
    auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (ec != std::errc() || ptr != t.data() + t.size() || value < INT32_MIN) {
      return Error{"bad content mask '" + std::string(t) + "': not a 32-bit integer"};
    }
    return std::uint32_t(std::int32_t(value));
  }
  if (!t.empty() && t.front() >= '0' && t.front() <= '9') {
    std::uint32_t value = 0;
    const bool hex = t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X');
    const char* first = t.data() + (hex ? 2 : 0);
    const char* last = t.data() + t.size();
    auto [ptr, ec] = std::from_chars(first, last, value, hex ? 16 : 10);
    if (ec != std::errc() || ptr != last) {
      return Error{"bad content mask '" + std::string(t) + "': not a 32-bit integer"};
    }
    return value;
  }
  return contentsFromString(t);
}

}  // namespace cmkit
