// Material names -> content flags: canonical names, the default rules of the
// reference data, and the content keywords of .mtr declarations.
//
// .mtr semantics (docs/materials.md lists them; where the original's rules are unknown these are
// cmkit's documented choices, modelled on the original's surface parameters):
// - a material starts as solid|opaque;
// - `solid`, `playerclip`, `monsterclip`, `moveableclip`, `ikclip`, `blood`,
//   `trigger`, `aassolid`, `aasobstacle`, `flashlight_trigger` add their flag;
// - `nonsolid` removes solid;
// - `water`, `areaportal`, `nocsg` (and the original's spelling of it,
//   `qer_nocarve`) add their flag and remove solid;
// - `translucent` removes opaque (the original does not mark translucent
//   materials opaque);
// - `twosided` makes polygons two-sided.
// Only tokens directly inside the material's braces count (stages, which are
// nested braces, are skipped). Keywords are case-insensitive.
#include <algorithm>
#include <filesystem>
#include <new>
#include <optional>
#include <system_error>

#include "cmkit/contents.h"
#include "cmkit/materials.h"
#include "cmkit/text_file.h"
#include "text/lexer.h"

namespace cmkit {

namespace {

using detail::Lexer;
using detail::SyntaxError;
using detail::Token;
using detail::TokenKind;

std::string lowerCase(std::string_view s) {
  std::string out(s);
  for (char& c : out) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return out;
}

bool startsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

/// Declaration types other than materials that .mtr files may hold (the
/// original's decl type names); their bodies are skipped.
bool isOtherDeclType(std::string_view lowered) {
  static constexpr std::string_view kTypes[] = {
      "table",  "skin",   "sound", "fx",           "particle", "articulatedfigure",
      "pda",    "video",  "email", "audio",        "model",    "entitydef",
      "mapdef", "export", "guide", "materialtype", "lipsync",  "camera",
      "af"};
  return std::find(std::begin(kTypes), std::end(kTypes), lowered) != std::end(kTypes);
}

/// Applies one top-level keyword of a material body.
void applyKeyword(std::string_view lowered, MaterialInfo& info) {
  struct Flag {
    std::string_view name;
    std::uint32_t add;
    bool clearSolid;
  };
  static constexpr Flag kFlags[] = {
      {"solid", contents::kSolid, false},
      {"water", contents::kWater, true},
      {"playerclip", contents::kPlayerClip, false},
      {"monsterclip", contents::kMonsterClip, false},
      {"moveableclip", contents::kMoveableClip, false},
      {"ikclip", contents::kIkClip, false},
      {"blood", contents::kBlood, false},
      {"trigger", contents::kTrigger, false},
      {"aassolid", contents::kAasSolid, false},
      {"aasobstacle", contents::kAasObstacle, false},
      {"flashlight_trigger", contents::kFlashlightTrigger, false},
      {"nonsolid", 0, true},
      {"areaportal", contents::kAreaPortal, true},
      {"nocsg", contents::kNoCsg, true},
      {"qer_nocarve", contents::kNoCsg, true},
  };
  for (const Flag& f : kFlags) {
    if (lowered == f.name) {
      if (f.clearSolid) info.contents &= ~contents::kSolid;
      info.contents |= f.add;
      return;
    }
  }
  if (lowered == "translucent") info.contents &= ~contents::kOpaque;
  if (lowered == "twosided") info.twoSided = true;
  if (lowered == "collision") info.collision = true;
}

std::string describe(const Token& t) {
  if (t.kind == TokenKind::End) return "the end of the file";
  if (t.kind == TokenKind::String) return "\"" + std::string(t.text) + "\"";
  return "'" + std::string(t.text) + "'";
}

}  // namespace

std::string MaterialTable::canonicalName(std::string_view name) {
  std::string out = lowerCase(name);
  std::replace(out.begin(), out.end(), '\\', '/');
  // The original cuts at the last dot ("a trailing file extension").
  const auto dot = out.rfind('.');
  if (dot != std::string::npos) out.resize(dot);
  return out;
}

MaterialInfo MaterialTable::defaultInfo(std::string_view c) {
  using namespace contents;
  MaterialInfo info;
  if (c == "textures/common/clip") {
    info.contents = kPlayerClip | kMonsterClip | kMoveableClip;
  } else if (c == "textures/common/player_clip") {
    info.contents = kPlayerClip;
  } else if (c == "textures/common/monster_clip") {
    info.contents = kMonsterClip;
  } else if (c == "textures/common/nodraw" || c == "textures/common/caulk") {
    info.contents = kSolid | kOpaque;
  } else if (c == "textures/common/nodrawsolid") {
    info.contents = kSolid;
  } else if (startsWith(c, "textures/common/trigger")) {
    info.contents = kTrigger;
  } else if (startsWith(c, "textures/common/noclip") || startsWith(c, "textures/editor/")) {
    info.contents = 0;
  } else if (c.find("water") != std::string_view::npos) {
    info.contents = kWater;
  } else {
    info.contents = kSolid | kOpaque;
  }
  // Doom 3's collision-only material for render models (mesh.h); its
  // contents stay those of the rules above.
  info.collision = c == "textures/common/collision";
  return info;
}

void MaterialTable::addMtrText(std::string_view text, const std::string& fileName) {
  Lexer lex(text);
  auto warn = [&](const SyntaxError& e) { warnings_.push_back(detail::toError(e, fileName).toString()); };
  auto warnAt = [&](const Token& t, const std::string& msg) { warn(Lexer::errorAt(t, msg)); };
  // The next token, or nullopt after warning about a malformed one (the
  // lexer has consumed it, so reading on makes progress).
  auto next = [&]() -> std::optional<Token> {
    try {
      return lex.next();
    } catch (const SyntaxError& e) {
      warn(e);
      return std::nullopt;
    }
  };
  // The next token without consuming it; nullopt (no warning) for a malformed one.
  auto peek = [&]() -> std::optional<Token> {
    try {
      return lex.peek();
    } catch (const SyntaxError&) {
      return std::nullopt;
    }
  };

  for (;;) {
    const std::optional<Token> first = next();
    if (!first) continue;
    const Token t = *first;
    if (t.kind == TokenKind::End) break;
    if (t.kind != TokenKind::Name && t.kind != TokenKind::String) {
      warnAt(t, "expected a declaration name, found " + describe(t) + " (skipped)");
      continue;
    }
    bool isMaterial = true;
    Token nameToken = t;
    if (t.kind == TokenKind::Name) {
      const std::string lowered = lowerCase(t.text);
      if (lowered == "material" || isOtherDeclType(lowered)) {
        isMaterial = lowered == "material";
        const auto name = peek();
        if (!name || (name->kind != TokenKind::Name && name->kind != TokenKind::String)) {
          warnAt(t, "expected a name after '" + std::string(t.text) + "' (declaration skipped)");
          continue;
        }
        nameToken = lex.next();
      }
    }
    const auto open = peek();
    if (!open || !open->isPunct('{')) {
      warnAt(nameToken,
             "expected '{' after the declaration name " + describe(nameToken) + " (declaration skipped)");
      continue;
    }
    (void)lex.next();

    // The body: top-level keywords only; nested braces (stages) skipped.
    MaterialInfo info;
    info.contents = contents::kSolid | contents::kOpaque;
    bool ok = true;
    int depth = 1;
    while (depth > 0) {
      const std::optional<Token> r = next();
      if (!r) {
        ok = false;
        continue;
      }
      const Token b = *r;
      if (b.kind == TokenKind::End) {
        warnAt(nameToken, "the file ends inside the declaration " + describe(nameToken) +
                              " (missing '}'; declaration skipped)");
        ok = false;
        break;
      }
      if (b.isPunct('{')) {
        ++depth;
      } else if (b.isPunct('}')) {
        --depth;
      } else if (depth == 1 && isMaterial && b.kind == TokenKind::Name) {
        applyKeyword(lowerCase(b.text), info);
      }
    }
    if (!ok) {
      warnAt(nameToken, "declaration " + describe(nameToken) + " skipped because of the errors above");
      continue;
    }
    if (!isMaterial) continue;
    const std::string key = canonicalName(nameToken.text);
    if (!declared_.emplace(key, info).second) {
      warnAt(nameToken,
             "material " + describe(nameToken) + " is declared again; the first declaration is kept");
    }
  }
}

Status MaterialTable::addMtrFile(const std::string& path) {
  Result<std::string> text = readTextFile(path);
  if (!text) return Error("material file: " + text.error().message, path);
  try {
    addMtrText(*text, path);
  } catch (const std::bad_alloc&) {
    return Error("out of memory while reading the material file", path);
  }
  return Ok{};
}

Status MaterialTable::addMtrDirectory(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return Error("not a directory of .mtr files", dir);
  std::vector<fs::path> files;
  for (fs::recursive_directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->is_regular_file(ec) && lowerCase(it->path().extension().string()) == ".mtr") {
      files.push_back(it->path());
    }
  }
  if (ec) return Error("cannot list the directory: " + ec.message(), dir);
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    auto s = addMtrFile(f.string());
    if (!s) return s;
  }
  return Ok{};
}

MaterialInfo MaterialTable::info(std::string_view name) const {
  const std::string key = canonicalName(name);
  const auto it = declared_.find(key);
  if (it != declared_.end()) return it->second;
  return defaultInfo(key);
}

}  // namespace cmkit
