// Internal: material names -> canonical names and collision info, looked up
// once per distinct name (used by the map compiler and the .cm reader).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "cmkit/materials.h"

namespace cmkit::detail {

/// The materials met while reading one map or .cm file: each distinct raw
/// name is canonicalised and looked up in the table once, and names with the
/// same canonical name share one index.
class MaterialCache {
 public:
  struct Material {
    std::string name;  ///< canonical
    MaterialInfo info;
  };

  /// `contentsOverride`: when set, every material gets these contents (the
  /// mesh builder's MeshBuildOptions::contents).
  explicit MaterialCache(const MaterialTable& table, std::optional<std::uint32_t> contentsOverride = {})
      : table_(table), contentsOverride_(contentsOverride) {}
  /// Index of the material (same canonical name -> same index).
  int find(std::string_view rawName);
  const Material& operator[](int i) const { return materials_[static_cast<std::size_t>(i)]; }
  const Material& get(std::string_view rawName) { return (*this)[find(rawName)]; }

 private:
  /// Lets the maps be searched with a string_view (no temporary string).
  struct NameHash {
    using is_transparent = void;
    std::size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
  };
  using IndexByName = std::unordered_map<std::string, int, NameHash, std::equal_to<>>;

  const MaterialTable& table_;
  std::optional<std::uint32_t> contentsOverride_;
  IndexByName byRaw_;
  IndexByName byCanonical_;
  std::vector<Material> materials_;
};

}  // namespace cmkit::detail
