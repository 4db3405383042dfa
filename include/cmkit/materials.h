// materials.h: material names -> content flags.
//
// Sources, in this order: .mtr declarations supplied by the user (only their
// content keywords are read), then the default rules of the reference data
// (textures/common/clip -> playerclip|monsterclip|moveableclip, ..., anything
// else -> solid|opaque); see docs/materials.md.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "cmkit/result.h"

namespace cmkit {

/// What a material means for collision.
struct MaterialInfo {
  /// Content flags (contents.h).
  std::uint32_t contents = 0;
  bool twoSided = false;  ///< polygons get a reversed copy
  /// A collision surface (.mtr keyword "collision"; by default only
  /// textures/common/collision): when a mesh has one, only its collision
  /// surfaces collide (mesh.h). Maps do not look at it.
  bool collision = false;
};

/// A table of materials. Immutable once filled; lookups are const.
class MaterialTable {
 public:
  /// Lower case, '\\' -> '/', a trailing file extension removed.
  static std::string canonicalName(std::string_view name);
  /// The default rules (exactly those the reference results were made with).
  static MaterialInfo defaultInfo(std::string_view canonical);

  /// Reads the material declarations of one .mtr text. Syntax errors in a
  /// declaration are reported as warnings (file:line) and that declaration
  /// is skipped; the rest is read.
  void addMtrText(std::string_view text, const std::string& fileName);
  /// Reads one .mtr file; error if it cannot be read.
  Status addMtrFile(const std::string& path);
  /// Reads every *.mtr file below a directory (sorted by path).
  Status addMtrDirectory(const std::string& dir);

  /// The material's info: declared, else the default rules.
  MaterialInfo info(std::string_view name) const;
  /// The material's content flags: info(name).contents.
  std::uint32_t contents(std::string_view name) const { return info(name).contents; }

  /// Warnings gathered while reading .mtr files.
  const std::vector<std::string>& warnings() const { return warnings_; }
  /// Number of materials declared by .mtr text read so far.
  std::size_t numDeclared() const { return declared_.size(); }

 private:
  std::unordered_map<std::string, MaterialInfo> declared_;
  std::vector<std::string> warnings_;
};

}  // namespace cmkit
