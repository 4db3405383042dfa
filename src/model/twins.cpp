// Reversed twins of polygons (twins.h).
#include "model/twins.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <type_traits>

namespace cmkit::detail {

namespace {

/// The bits of a Real (to compare values exactly, sign of zero included).
using RealBits = std::conditional_t<sizeof(Real) == 8, std::uint64_t, std::uint32_t>;

/// Whether b is exactly -a, sign of zero included (what negating every
/// coordinate of a plane gives).
bool isNegated(Real a, Real b) { return std::bit_cast<RealBits>(b) == std::bit_cast<RealBits>(Real(-a)); }

}  // namespace

std::ptrdiff_t reversedFrom(std::span<const std::int32_t> a, std::span<const std::int32_t> b) {
  const std::size_t n = a.size();
  if (n == 0 || n != b.size()) return -1;
  for (std::size_t s = 0; s < n; ++s) {
    if (a[s] != -b[0]) continue;
    bool reversed = true;
    for (std::size_t k = 1; reversed && k < n; ++k) reversed = b[k] == -a[(s + n - k) % n];
    if (reversed) return std::ptrdiff_t(s);
  }
  return -1;
}

bool isTwin(const ModelArrays& m, const CmPolygon& a, const CmPolygon& b) {
  if (a.numEdges != b.numEdges || a.contents != b.contents || !isNegated(a.plane.dist, b.plane.dist))
    return false;
  for (int k = 0; k < 3; ++k)
    if (!isNegated(a.plane.normal[k], b.plane.normal[k])) return false;
  const std::span<const std::int32_t> ea = m.edgesOf(a), eb = m.edgesOf(b);
  // What a reversed copy made by the builders has (enough: each edge then
  // has its negation in the other list). Any other order is checked edge by
  // edge below.
  if (reversedFrom(ea, eb) >= 0) return true;
  const auto has = [](std::span<const std::int32_t> edges, std::int32_t e) {
    return std::find(edges.begin(), edges.end(), e) != edges.end();
  };
  for (const std::int32_t e : ea)
    if (!has(eb, -e)) return false;
  for (const std::int32_t e : eb)
    if (!has(ea, -e)) return false;
  return true;
}

std::vector<std::int32_t> findTwins(const ModelArrays& m, std::span<const std::uint32_t> polygons) {
  std::vector<std::int32_t> twin(polygons.size(), -1);
  // Neighbours first, in one pass: the builders add a two-sided polygon's
  // reversed copy right after it, so a mesh's pairs are found here without
  // the hashing and sorting below, whose reads of the polygons in hash order
  // were a cache miss each (about a tenth of building a large two-sided
  // mesh's model and ray index).
  for (std::size_t i = 0; i + 1 < polygons.size(); ++i)
    if (isTwin(m, m.polygons[polygons[i]], m.polygons[polygons[i + 1]])) {
      twin[i] = std::int32_t(i + 1);
      twin[i + 1] = std::int32_t(i);
      ++i;
    }
  // The others by a hash of their edges.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keys;
  std::vector<std::int32_t> edges;
  for (std::uint32_t i = 0; i < polygons.size(); ++i) {
    if (twin[i] >= 0) continue;
    const auto list = m.edgesOf(m.polygons[polygons[i]]);
    edges.assign(list.begin(), list.end());
    for (std::int32_t& e : edges) e = std::abs(e);
    std::sort(edges.begin(), edges.end());
    std::uint64_t h = 14695981039346656037ull;  // FNV-1a over the edge numbers
    for (const std::int32_t e : edges) h = (h ^ std::uint64_t(std::uint32_t(e))) * 1099511628211ull;
    keys.emplace_back(h, i);
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t run = 0; run < keys.size();) {
    std::size_t end = run + 1;
    while (end < keys.size() && keys[end].first == keys[run].first) ++end;
    for (std::size_t a = run; a < end; ++a) {
      const std::uint32_t ia = keys[a].second;
      if (twin[ia] >= 0) continue;
      for (std::size_t b = a + 1; b < end; ++b) {
        const std::uint32_t ib = keys[b].second;
        if (twin[ib] < 0 && isTwin(m, m.polygons[polygons[ia]], m.polygons[polygons[ib]])) {
          twin[ia] = std::int32_t(ib);
          twin[ib] = std::int32_t(ia);
          break;
        }
      }
    }
    run = end;
  }
  return twin;
}

}  // namespace cmkit::detail
