// Map primitives -> brushes and polygons (the original's ConvertBrush,
// ConvertBrushSides, ConvertPatch and CreatePatchPolygons).
#include <cstdlib>

#include "cmkit/contents.h"
#include "compile/builder.h"
#include "geometry/patch.h"

namespace cmkit::detail {

namespace {

/// The face of brush side `side`: the side's plane clipped by every other
/// plane (inward-facing windings of the outward brush planes).
Winding sideWinding(const std::vector<Plane>& planes, std::size_t side) {
  Winding w = Winding::baseForPlane(planes[side].flipped());
  for (std::size_t j = 0; j < planes.size() && !w.empty(); ++j) {
    if (j != side) w.clipInPlace(planes[j].flipped(), 0);
  }
  return w;
}

}  // namespace

ModelBuilder::ModelBuilder(const MapEntity& entity, std::string name, MaterialCache& materials,
                           std::vector<std::string>* warnings, const ProcBsp* proc)
    : name_(std::move(name)),
      materials_(materials),
      warnings_(warnings),
      proc_(proc && proc->usable() ? proc : nullptr) {
  entity_ = &entity;
}

ModelBuilder::ModelBuilder(const TriangleMesh& mesh, std::string name, MaterialCache& materials,
                           std::vector<std::string>* warnings)
    : name_(std::move(name)), materials_(materials), warnings_(warnings) {
  mesh_ = &mesh;
}

void ModelBuilder::warn(const std::string& message) {
  if (!warnings_) return;
  std::string line = "model \"" + name_ + "\": " + message;
  // A message this model gave before (a degenerate patch can drop thousands
  // of polygons) updates its first line with a count instead of repeating.
  auto [it, first] = warningSlots_.try_emplace(message, WarningSlot{warnings_->size(), 0});
  if (++it->second.count > 1) {
    (*warnings_)[it->second.index] = line + " (" + std::to_string(it->second.count) + " times)";
    return;
  }
  warnings_->push_back(std::move(line));
}

std::vector<ModelBuilder::BrushPrimitive> ModelBuilder::convertBrushes() {
  const auto& prims = entity_->primitives;
  std::vector<BrushPrimitive> brushPrims(prims.size());
  for (std::size_t i = 0; i < prims.size(); ++i) {
    if (const auto* mapBrush = std::get_if<MapBrush>(&prims[i])) {
      convertBrush(*mapBrush, static_cast<int>(i), brushPrims[i]);
    }
  }
  return brushPrims;
}

void ModelBuilder::convertPrimitivesToPolygons(std::vector<BrushPrimitive>& brushPrims) {
  const auto& prims = entity_->primitives;
  for (std::size_t i = 0; i < prims.size(); ++i) {
    if (const auto* patch = std::get_if<MapPatch>(&prims[i])) {
      convertPatch(*patch, static_cast<int>(i));
    } else {
      convertBrushSides(std::get<MapBrush>(prims[i]), brushPrims[i]);
      brushPrims[i] = BrushPrimitive{};  // free the cached windings
    }
  }
}

void ModelBuilder::convertBrush(const MapBrush& mapBrush, int primitiveNum, BrushPrimitive& out) {
  const std::size_t numSides = mapBrush.sides.size();
  out.primitiveNum = primitiveNum;
  out.planes.resize(numSides);
  for (std::size_t i = 0; i < numSides; ++i) {
    out.planes[i] = mapBrush.sides[i].plane;
    out.planes[i].fixDegeneracies(tol::kDegenerateDistEpsilon);
  }
  if (numSides < 4) {
    warn("brush (primitive " + std::to_string(primitiveNum) + ", line " + std::to_string(mapBrush.line) +
         ") has " + std::to_string(numSides) + " sides: it does not enclose a volume");
  }
  // Bounds, contents and material come from sides 0..n-2 only (the
  // original's loop stops one early as it only needs the bounds).
  Bounds bounds;
  std::uint32_t contents = 0;
  int material = kNone;
  bool anyPoints = false;
  if (numSides > 1) out.windings.resize(numSides - 1);
  for (std::size_t i = 0; i + 1 < numSides; ++i) {
    Winding& w = out.windings[i];
    w = sideWinding(out.planes, i);
    for (const Vec3& p : w.points()) bounds.addPoint(p);
    anyPoints = anyPoints || !w.empty();
    material = materials_.find(mapBrush.sides[i].material);
    contents |= materials_[material].info.contents & kUsefulContents;
  }
  if (contents == 0) return;
  if (!anyPoints) {
    warn("brush (primitive " + std::to_string(primitiveNum) + ", line " + std::to_string(mapBrush.line) +
         ") is empty: its planes enclose no volume (kept, as the original does, with cleared bounds)");
  }
  BBrush b;
  b.bounds = bounds;
  b.contents = contents;
  b.material = material;
  b.primitiveNum = primitiveNum;
  b.planes = out.planes;
  brushes_.push_back(std::move(b));
  addBrushToNode(0, static_cast<int>(brushes_.size()) - 1);
}

void ModelBuilder::convertBrushSides(const MapBrush& mapBrush, BrushPrimitive& prim) {
  const std::size_t numSides = mapBrush.sides.size();
  for (std::size_t i = 0; i < numSides; ++i) {
    const int material = materials_.find(mapBrush.sides[i].material);
    if ((materials_[material].info.contents & kUsefulContents) == 0) continue;
    // the windings of all sides but the last were made by convertBrush
    Winding w = i + 1 < numSides ? std::move(prim.windings[i]) : sideWinding(prim.planes, i);
    if (!w.empty()) polygonFromWinding(w, prim.planes[i], material, prim.primitiveNum);
  }
}

void ModelBuilder::convertPatch(const MapPatch& patch, int primitiveNum) {
  const int material = materials_.find(patch.material);
  if ((materials_[material].info.contents & kUsefulContents) == 0) return;
  const PatchGrid mesh = subdividePatchForCollision(patch);
  if (mesh.points.empty()) {
    warn("patch (primitive " + std::to_string(primitiveNum) + ", line " + std::to_string(patch.line) +
         ") could not be subdivided; skipped");
    return;
  }
  // Patch polygons carry a negative primitive number.
  const int polyPrimitive = -primitiveNum;
  const int width = mesh.width;
  auto at = [&](int k) -> const Vec3& { return mesh.points[static_cast<std::size_t>(k)]; };  // row-major grid
  for (int i = 0; i < mesh.width - 1; ++i) {
    for (int j = 0; j < mesh.height - 1; ++j) {
      const int v1 = j * width + i;
      const int v2 = v1 + 1;
      const int v3 = v1 + width + 1;
      const int v4 = v1 + width;
      Plane plane;
      plane.normal = (at(v2) - at(v1)).cross(at(v3) - at(v1));
      if (normalizeLikeOriginal(plane.normal) != 0) {
        plane.fixDegeneracies(0);  // the original's Normalize fixes degenerate normals
        plane.fitThroughPoint(at(v1));
        const Real dot = plane.distance(at(v4));
        Winding w;
        if (std::fabs(dot) < tol::kPatchQuadPlanarEpsilon) {
          w.add(at(v1));
          w.add(at(v2));
          w.add(at(v3));
          w.add(at(v4));
          polygonFromWinding(w, plane, material, polyPrimitive);
          continue;
        }
        w.add(at(v1));
        w.add(at(v2));
        w.add(at(v3));
        polygonFromWinding(w, plane, material, polyPrimitive);
      }
      // the other triangle
      plane = Plane{};
      plane.normal = (at(v3) - at(v1)).cross(at(v4) - at(v1));
      if (normalizeLikeOriginal(plane.normal) != 0) {
        plane.fixDegeneracies(0);
        plane.fitThroughPoint(at(v1));
        Winding w;
        w.add(at(v1));
        w.add(at(v3));
        w.add(at(v4));
        polygonFromWinding(w, plane, material, polyPrimitive);
      }
    }
  }
}

}  // namespace cmkit::detail
