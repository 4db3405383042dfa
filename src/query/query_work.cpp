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
  auto grow = [](auto& v, std::size_t n) {
    if (v.size() < n) v.resize(n);
  };
  const std::size_t np = model.polygons().size(), nb = model.brushes().size();
  const std::size_t ne = model.edges().size(), nv = model.vertices().size();
  grow(polygonChecked, np);
  if constexpr (kQueryStats) grow(polygonMet, np);
  grow(brushChecked, nb);
  grow(edgeChecked, ne);
  grow(edgePairs, ne);
  grow(vertexChecked, nv);
  if (++generation == 0) {  // wrapped: clear every mark once every 2^32 queries
    std::fill(polygonChecked.begin(), polygonChecked.end(), 0u);
    std::fill(polygonMet.begin(), polygonMet.end(), 0u);
    std::fill(brushChecked.begin(), brushChecked.end(), 0u);
    std::fill(edgeChecked.begin(), edgeChecked.end(), 0u);
    std::fill(edgePairs.begin(), edgePairs.end(), EdgePairs{});
    std::fill(vertexChecked.begin(), vertexChecked.end(), 0u);
    generation = 1;
  }
}

}  // namespace cmkit::detail
