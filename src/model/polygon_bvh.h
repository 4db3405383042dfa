// Internal: cmkit's own query layout of a model's polygons, made once with
// the model (query_data.h) beside the .cm file's axial BSP tree: a 4-wide
// bounding volume hierarchy. Every polygon is in exactly one leaf (the BSP
// tree lists a polygon at every node it straddles, so its walks mark what
// they met); a leaf is one CullBlock of up to kLanes polygons (a polygon
// and its reversed twin, the two sides of a two-sided surface, in one
// lane), so the culls of a leaf are one block's. Only kCullBlocks builds
// (float lanes) make one; the queries fall back to the BSP tree without it.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "model/query_blocks.h"
#include "util/aligned_allocator.h"

namespace cmkit::detail {

/// An inner node: the bounds of its up to kLanes children, one array per
/// coordinate (lane j is child j). child[j] >= 0: node child[j]; < 0: leaf
/// ~child[j]. An unused lane has inverted bounds (min > max), which no box
/// touches. (Two whole cache lines: 112 bytes at 16-byte alignment would
/// straddle a third line every other node.)
struct alignas(64) BvhNode {
  float min[3][kLanes];
  float max[3][kLanes];
  std::int32_t child[kLanes];
  /// The contents of the polygons below each child, OR'ed (0: unused lane).
  std::uint32_t contents[kLanes];
};
static_assert(sizeof(BvhNode) == 128);

/// A leaf: its polygons' culls, on whole cache lines (the first two hold
/// what the first cull reads: bounds and contents), their planes' distances
/// (with CullBlock::normal, the planes) and their numbers (in the leaf: in
/// an array of their own, the number was one more load the polygon's tests
/// waited for), each with a flag for a reversed twin (model/twins.h): a
/// two-sided surface's two sides take one lane, whose culls are the same
/// for both but the facing one, which tells the sides apart (the twin's
/// plane is exactly the lane's negated, its bounds and contents the same).
/// The fourth cache line holds the rest of what a translation's test reads
/// of a lane's polygons (so not the model's polygon records, read at
/// random): their materials, twins, edge counts, and where their edge uses
/// start (PolygonBvh::uses, the leaf's one after another).
struct alignas(64) BvhLeaf : CullBlock {
  /// A lane's polygon number with this bit: it has a twin (BvhLeaf::twin).
  static constexpr std::int32_t kHasTwin = std::int32_t(1) << 30;
  /// The sign bit: set in an unused lane's -1.
  static constexpr std::int32_t kUnusedBit = std::int32_t(0x80000000u);
  Real dist[kLanes];
  /// Lane j's polygon number, with kHasTwin when it has a twin (-1: unused).
  std::int32_t polygon[kLanes];
  /// Lane j's polygon's reversed twin (-1: none).
  std::int32_t twin[kLanes];
  /// The materials of lane j's polygon and of its twin (CmPolygon::material).
  std::int32_t material[kLanes];
  std::int32_t twinMaterial[kLanes];
  /// The leaf's edge uses start at PolygonBvh::uses[firstUse]: lane 0's
  /// polygon's numEdges[0], its twin's numEdges[0] when the twin's are
  /// stored (twinStart[0] == kStoredTwin; a twin has as many edges as its
  /// polygon), lane 1's, ..., each polygon's starting a cache line
  /// (usesStride).
  std::uint32_t firstUse;
  std::uint16_t numEdges[kLanes];  ///< lane j's polygon's (CmPolygon::numEdges)
  /// How lane j's twin's edge uses are had: kStoredTwin, stored after the
  /// polygon's; else s, made from the polygon's (twinCorners): the twin's
  /// edge k is the polygon's edge (s + n - k) mod n used the other way
  /// round, as the builders' reversed copies are (model/twins.h). (Made,
  /// a twin's corners cost no memory: a two-sided mesh's uses were half
  /// its twins'.) 0 in a lane without a twin.
  std::uint8_t twinStart[kLanes];
  /// twinStart of a lane whose twin's uses are stored.
  static constexpr std::uint8_t kStoredTwin = 0xFF;
  /// Twins of at most this many edges have their uses made (the queries
  /// make them on the stack); others' are stored.
  static constexpr std::size_t kMaxMadeTwinEdges = 8;
  /// The uses a polygon of n edges takes in PolygonBvh::uses: n, rounded up
  /// to whole cache lines (a triangle's 48 bytes are one line, not two
  /// lines three times in four).
  static std::size_t usesStride(std::size_t n) { return (n + kUsesPerLine - 1) & ~(kUsesPerLine - 1); }
  static constexpr std::size_t kUsesPerLine = 64 / sizeof(PolygonCorner);
  /// Where each lane's polygon's edge uses start, and its twin's when stored.
  struct UseStarts {
    std::size_t lane[kLanes];    ///< lane j's polygon's
    std::size_t stride[kLanes];  ///< usesStride of lane j's polygon: a stored twin's follow
    std::size_t of(std::size_t j) const { return lane[j]; }
    std::size_t twinOf(std::size_t j) const { return lane[j] + stride[j]; }
  };
  /// The lanes' use starts, as a running sum over every lane (once a leaf:
  /// a sum up to the lane asked for ended its loop at a lane the branch
  /// could not foresee).
  UseStarts useStarts() const {
    UseStarts u;
    std::size_t at = firstUse;
    for (std::size_t j = 0; j < kLanes; ++j) {
      u.lane[j] = at;
      u.stride[j] = usesStride(numEdges[j]);
      at += u.stride[j] << unsigned(twinStart[j] == kStoredTwin);  // (only a lane with a twin's is)
    }
    return u;
  }
  /// Whether lane j's twin's uses are made (twinCorners), not stored (lane
  /// j has a twin).
  bool twinMade(std::size_t j) const { return twinStart[j] != kStoredTwin; }
  /// Lane j's twin's corners made from its polygon's (`corners`, n of
  /// them, n at most kMaxMadeTwinEdges) into out[0 .. n - 1]: the corners
  /// the twin's stored uses would hold, bit for bit (twinStart).
  void twinCorners(std::size_t j, const PolygonCorner* corners, PolygonCorner* out) const {
    const std::size_t n = numEdges[j];
    // Twin edge k is the polygon's edge m = (s + n - k) mod n reversed: it
    // starts where that one ends, at the polygon's corner m + 1.
    for (std::size_t k = 0, m = twinStart[j]; k < n; ++k, m = (m == 0 ? n : m) - 1) {
      const PolygonCorner& c = corners[m];
      out[k].entry = PolygonCorner::encode(-c.edgeNum(), c.internal());
      out[k].p = corners[m + 1 == n ? 0 : m + 1].p;
    }
  }
  /// Lane j's polygon number (lane j used).
  std::int32_t polygonAt(std::size_t j) const { return polygon[j] & ~kHasTwin; }
  /// The used lanes whose polygon has a twin (bit j for lane j).
  unsigned twinLanes() const {
    unsigned lanes = 0;
    for (std::size_t j = 0; j < kLanes; ++j)
      lanes |= unsigned((polygon[j] & (kHasTwin | kUnusedBit)) == kHasTwin) << j;  // (used, with a twin)
    return lanes;
  }
};
// (Only the float builds that make the hierarchy: a double build's blocks
// are twice as large, and it walks the BSP tree.)
static_assert(sizeof(Real) != sizeof(float) || sizeof(BvhLeaf) == 256);

/// The hierarchy of a model's polygons.
struct PolygonBvh {
  /// Node 0 is the root (none for a model without polygons).
  std::vector<BvhNode> nodes;
  /// Leaf b's polygons' culls (bounds, contents, normal); an unused lane
  /// has contents 0 and inverted bounds.
  std::vector<BvhLeaf> leaves;
  /// The leaves' polygons' edge entries as corners (query_blocks.h,
  /// PolygonCorner: the entry, its internal flag and where the edge starts),
  /// leaf by leaf in the leaves' order (BvhLeaf::firstUse): a leaf's in one
  /// run of memory, the leaves near one another in space near one another
  /// here, each polygon's from the start of a cache line (the entries up to
  /// the next line's unused); a twin's only where they are not made from
  /// its polygon's (BvhLeaf::twinStart). (The model's edge uses in another
  /// order, with the position of a vertex in place of the edge's two vertex
  /// numbers, for the translations' tests: a sealed model's polygons' edges
  /// close a loop.)
  std::vector<PolygonCorner, AlignedAllocator<PolygonCorner, 64>> uses;
  /// Inner nodes on the longest path from the root (the walks' stacks hold
  /// at most (kLanes - 1) * depth + 1 entries).
  std::size_t depth = 0;

  bool empty() const { return nodes.empty(); }
  /// Entries a walk's stack needs.
  std::size_t stackSize() const { return (kLanes - 1) * depth + 1; }
};

/// Models with at most this many polygons get no hierarchy (their
/// translations walk the BSP tree): a walk of a small model's tree meets a
/// handful of polygons as fast, and a hierarchy's nodes and leaves (128 and
/// 256 bytes, a leaf for about three polygons, besides a copy of their edge
/// uses) would outweigh the model's own arrays (a map's small brush
/// entities: 1.6x their arrays at 32, when a leaf was 192 bytes).
inline constexpr std::size_t kBvhMinPolygons = 256;

/// The hierarchy of the model's polygons (the arrays' numbers in range);
/// empty for a model with kBvhMinPolygons or fewer, or with a polygon of
/// more than 65 535 edges (BvhLeaf::numEdges). `uses`: the model's edge
/// uses (QueryData::edgeUses), copied into the leaves' order as corners
/// (a twin's where BvhLeaf::twinStart says so).
/// Made top-down, splitting each set of polygons in two at the cheapest of
/// a few planes along its widest axis by the surface-area cost (binned), into
/// up to kLanes children per node; sets of up to kLanes polygons are leaves.
PolygonBvh buildPolygonBvh(const ModelArrays& m, std::span<const EdgeUse> uses);

}  // namespace cmkit::detail
