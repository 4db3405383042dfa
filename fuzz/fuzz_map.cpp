// Fuzz target: .map text -> parser -> map compiler -> models (validated) ->
// queries.
#include <algorithm>
#include <variant>

#include "cmkit/compile.h"
#include "cmkit/map.h"
#include "fuzz_common.h"

namespace {

// Per-exec cost caps of this target (not of the library): most of a naive
// run's time went into tessellating patches that mutation had made huge (a
// control point at 1e13 subdivides a patch to the library's limit of a
// million grid points, tens of milliseconds). Such maps are still parsed
// here; the compiler's handling of them is covered by unit tests
// (BuildBadInput.EnormousPatchPointsStillGiveClosedOutlines and the patch
// limits in test_patch.cpp). Capped: patches wider than kMaxControlPoints
// control points in all, patchDef3 subdivisions above kMaxSubdivisions, and
// patches whose control points span more than kMaxPatchExtent units (the
// subdivision a patchDef2 gets grows with its size over the 24-unit error).
constexpr int kMaxControlPoints = 15 * 15;
constexpr int kMaxSubdivisions = 32;
constexpr cmkit::Real kMaxPatchExtent = 8192;

bool cheapToBuild(const cmkit::MapFile& map) {
  for (const cmkit::MapEntity& e : map.entities) {
    for (const cmkit::MapPrimitive& primitive : e.primitives) {
      const auto* patch = std::get_if<cmkit::MapPatch>(&primitive);
      if (!patch) continue;
      if (patch->width * patch->height > kMaxControlPoints) return false;
      if (patch->explicitSubdivisions &&
          std::max(patch->horzSubdivisions, patch->vertSubdivisions) > kMaxSubdivisions)
        return false;
      cmkit::Bounds b;
      for (const cmkit::Vec3& p : patch->points) b.addPoint(p);
      const cmkit::Vec3 size = b.max - b.min;
      if (!patch->points.empty() && !(std::max({size.x, size.y, size.z}) <= kMaxPatchExtent)) return false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > cmkit::fuzz::kMaxInputBytes) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto map = cmkit::parseMapText(text, "fuzz.map");
  if (!map || !cheapToBuild(*map)) return 0;
  for (const cmkit::MapEntity& e : map->entities) {
    (void)e.origin();
    (void)e.axis();
  }
  auto models = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!models) return 0;
  for (const cmkit::ModelPtr& m : models->models) cmkit::fuzz::requireValid(*m, "the map compiler");
  cmkit::fuzz::exerciseModels(models->models);
  return 0;
}
