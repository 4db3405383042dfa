// Material lookups: see material_cache.h.
#include "model/material_cache.h"

namespace cmkit::detail {

int MaterialCache::find(std::string_view rawName) {
  const auto it = byRaw_.find(rawName);
  if (it != byRaw_.end()) return it->second;
  std::string canonical = MaterialTable::canonicalName(rawName);
  int index;
  const auto cit = byCanonical_.find(canonical);
  if (cit != byCanonical_.end()) {
    index = cit->second;
  } else {
    index = static_cast<int>(materials_.size());
    MaterialInfo info = table_.info(canonical);
    if (contentsOverride_) info.contents = *contentsOverride_;
    materials_.push_back({canonical, info});
    byCanonical_.emplace(std::move(canonical), index);
  }
  byRaw_.emplace(rawName, index);
  return index;
}

}  // namespace cmkit::detail
