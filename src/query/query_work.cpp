// QueryWork, the caller's scratch memory for queries: its members, and the
// set-up of its marks for a model (QueryScratch::begin, trace_work.h).
#include <algorithm>
#include <memory>

#include "query/rotate_work.h"  // QueryScratch owns a RotationWork
#include "query/trace_work.h"

namespace cmkit {

QueryWork::QueryWork() : scratch_(std::make_unique<detail::QueryScratch>()) {}
QueryWork::~QueryWork() = default;
QueryWork::QueryWork(QueryWork&&) noexcept = default;
QueryWork& QueryWork::operator=(QueryWork&&) noexcept = default;
const QueryStats& QueryWork::stats() const { return scratch_->stats; }
void QueryWork::resetStats() { scratch_->stats = QueryStats{}; }
bool queryStatsEnabled() { return detail::kQueryStats; }

}  // namespace cmkit

namespace cmkit::detail {

void QueryScratch::begin(const CollisionModel& model) {
  const std::size_t np = model.polygons().size(), nb = model.brushes().size();
  const std::size_t ne = model.edges().size(), nv = model.vertices().size();
  for (FeatureMarks* m : {&polygonChecked, &polygonMet, &brushChecked, &edgeChecked, &vertexChecked})
    m->clear();
  polygonChecked.grow(np);
  if constexpr (kQueryStats) polygonMet.grow(np);
  brushChecked.grow(nb);
  edgeChecked.grow(ne);
  if (edgePairs.size() < ne) edgePairs.resize(ne);
  vertexChecked.grow(nv);
  if (++generation == 0) {  // wrapped: clear the caches once every 2^32 queries
    std::fill(edgePairs.begin(), edgePairs.end(), EdgePairs{});
    generation = 1;
  }
}

}  // namespace cmkit::detail
