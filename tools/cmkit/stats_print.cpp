// Model statistics in the original's layout and as JSON.
#include "stats_print.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace cmkit::cli {

namespace {

// Sizes of the original's structures in a 64-bit build (they decide the
// memory figures the original prints).
constexpr long long kVertexSize = 24;       // cm_vertex_t
constexpr long long kEdgeSize = 36;         // cm_edge_t
constexpr long long kPolygonBaseSize = 64;  // cm_polygon_t with one edge
constexpr long long kPolygonEdgeSize = 4;   // each further edge
constexpr long long kBrushBaseSize = 64;    // cm_brush_t with one plane
constexpr long long kBrushPlaneSize = 16;   // each further plane
constexpr long long kNodeSize = 48;         // cm_node_t
constexpr long long kReferenceSize = 16;    // cm_polygonRef_t, cm_brushRef_t

// printf("%g"), as the original prints bounds.
std::string g(float v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", static_cast<double>(v));
  return buf;
}

}  // namespace

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          out += fmt::format("\\u{:04x}", static_cast<unsigned>(static_cast<unsigned char>(c)));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

namespace {

// A float for JSON: finite numbers as %g would lose digits, so use the
// shortest exact representation; non-finite values as null.
std::string jsonFloat(float v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{}", v);
}

void printCounts(std::FILE* out, const ModelCounts& c) {
  auto kb = [](long long bytes) { return bytes >> 10; };
  fmt::print(out, "{:6} vertices ({} KB)\n", c.vertices, kb(c.vertexBytes));
  fmt::print(out, "{:6} edges ({} KB)\n", c.edges, kb(c.edgeBytes));
  fmt::print(out, "{:6} polygons ({} KB)\n", c.polygons, kb(c.polygonBytes));
  fmt::print(out, "{:6} brushes ({} KB)\n", c.brushes, kb(c.brushBytes));
  fmt::print(out, "{:6} nodes ({} KB)\n", c.nodes, kb(c.nodeBytes));
  fmt::print(out, "{:6} polygon refs ({} KB)\n", c.polygonRefs, kb(c.polygonRefBytes));
  fmt::print(out, "{:6} brush refs ({} KB)\n", c.brushRefs, kb(c.brushRefBytes));
  fmt::print(out, "{:6} internal edges\n", c.internalEdges);
  fmt::print(out, "{:6} sharp edges\n", c.sharpEdges);
  fmt::print(out, "{:6} contained polygons removed\n", c.containedPolygonsRemoved);
  fmt::print(out, "{:6} polygons merged\n", c.polygonsMerged);
  fmt::print(out, "{:6} KB total memory used\n", kb(c.totalBytes));
}

std::string countsJson(const ModelCounts& c) {
  return fmt::format(
      "\"vertices\": {}, \"edges\": {}, \"polygons\": {}, \"brushes\": {}, \"nodes\": {}, "
      "\"polygonRefs\": {}, \"brushRefs\": {}, \"internalEdges\": {}, \"sharpEdges\": {}, "
      "\"containedPolygonsRemoved\": {}, \"polygonsMerged\": {}, \"memoryBytes\": {}",
      c.vertices, c.edges, c.polygons, c.brushes, c.nodes, c.polygonRefs, c.brushRefs, c.internalEdges,
      c.sharpEdges, c.containedPolygonsRemoved, c.polygonsMerged, c.totalBytes);
}

// The memory the models take in cmkit (modelMemory), summed.
ModelMemory cmkitMemory(std::span<const ModelPtr> models) {
  ModelMemory sum;
  for (const ModelPtr& m : models) {
    const ModelMemory one = modelMemory(*m);
    sum.arrays += one.arrays;
    sum.queryData += one.queryData;
  }
  return sum;
}

}  // namespace

ModelCounts& ModelCounts::operator+=(const ModelCounts& o) {
  vertices += o.vertices;
  edges += o.edges;
  polygons += o.polygons;
  brushes += o.brushes;
  nodes += o.nodes;
  polygonRefs += o.polygonRefs;
  brushRefs += o.brushRefs;
  internalEdges += o.internalEdges;
  sharpEdges += o.sharpEdges;
  containedPolygonsRemoved += o.containedPolygonsRemoved;
  polygonsMerged += o.polygonsMerged;
  vertexBytes += o.vertexBytes;
  edgeBytes += o.edgeBytes;
  polygonBytes += o.polygonBytes;
  brushBytes += o.brushBytes;
  nodeBytes += o.nodeBytes;
  polygonRefBytes += o.polygonRefBytes;
  brushRefBytes += o.brushRefBytes;
  totalBytes += o.totalBytes;
  return *this;
}

ModelCounts countModel(const CollisionModel& model) {
  ModelCounts c;
  c.vertices = static_cast<long long>(model.vertices().size());
  c.edges = static_cast<long long>(model.edges().size());
  c.polygons = static_cast<long long>(model.polygons().size());
  c.brushes = static_cast<long long>(model.brushes().size());
  c.nodes = model.nodes().empty() ? 0 : static_cast<long long>(model.nodes().size()) - 1;
  c.polygonRefs = static_cast<long long>(model.polygonRefs().size());
  c.brushRefs = static_cast<long long>(model.brushRefs().size());
  c.internalEdges = model.stats().internalEdges;
  c.sharpEdges = model.stats().sharpEdges;
  c.containedPolygonsRemoved = model.stats().containedPolygonsRemoved;
  c.polygonsMerged = model.stats().polygonsMerged;
  c.vertexBytes = c.vertices * kVertexSize;
  c.edgeBytes = c.edges * kEdgeSize;
  for (const CmPolygon& p : model.polygons()) {
    c.polygonBytes += kPolygonBaseSize + (static_cast<long long>(p.numEdges) - 1) * kPolygonEdgeSize;
  }
  for (const CmBrush& b : model.brushes()) {
    c.brushBytes += kBrushBaseSize + (static_cast<long long>(b.numPlanes) - 1) * kBrushPlaneSize;
  }
  c.nodeBytes = c.nodes * kNodeSize;
  c.polygonRefBytes = c.polygonRefs * kReferenceSize;
  c.brushRefBytes = c.brushRefs * kReferenceSize;
  c.totalBytes = c.vertexBytes + c.edgeBytes + c.polygonBytes + c.brushBytes + c.nodeBytes +
                 c.polygonRefBytes + c.brushRefBytes;
  return c;
}

void printStatsText(std::FILE* out, std::span<const ModelPtr> models, const StatsContext& context) {
  ModelCounts total;
  for (const ModelPtr& m : models) total += countModel(*m);
  fmt::print(out, "collision data:\n");
  fmt::print(out, "{:6} models\n", models.size());
  printCounts(out, total);
  if (context.milliseconds >= 0) fmt::print(out, "{} msec to build collision data.\n", context.milliseconds);
  fmt::print(out, "proc BSP used for pruning: {}\n", context.procFile.empty() ? "no" : "yes");
  const ModelMemory memory = cmkitMemory(models);
  if (context.cmkitMemory)
    fmt::print(out, "in cmkit: {} KB of model arrays, {} KB of query data beside them ({:.2f}x)\n",
               memory.arrays >> 10, memory.queryData >> 10,
               memory.arrays == 0 ? 0.0 : double(memory.queryData) / double(memory.arrays));
  if (context.entities >= 0) fmt::print(out, "entities: {}\n", context.entities);
  if (!context.perModel) return;
  int index = 0;
  for (const ModelPtr& m : models) {
    const Bounds& b = m->bounds();
    fmt::print(out, "model {} \"{}\": bounds ({} {} {})-({} {} {}) contents {}\n", index++, m->name(),
               g(b.min.x), g(b.min.y), g(b.min.z), g(b.max.x), g(b.max.y), g(b.max.z), m->contents());
    printCounts(out, countModel(*m));
  }
}

std::string statsJson(std::span<const ModelPtr> models, const StatsContext& context) {
  ModelCounts total;
  std::string modelsJson;
  int index = 0;
  for (const ModelPtr& m : models) {
    const ModelCounts c = countModel(*m);
    total += c;
    const Bounds& b = m->bounds();
    if (!modelsJson.empty()) modelsJson += ",\n";
    modelsJson += fmt::format(
        "    {{\"index\": {}, \"name\": {}, \"bounds\": [[{}, {}, {}], [{}, {}, {}]], \"contents\": {}, {}}}",
        index++, jsonString(m->name()), jsonFloat(b.min.x), jsonFloat(b.min.y), jsonFloat(b.min.z),
        jsonFloat(b.max.x), jsonFloat(b.max.y), jsonFloat(b.max.z), m->contents(), countsJson(c));
  }
  std::string s = "{\n";
  s += fmt::format("  \"source\": {},\n", jsonString(context.source));
  if (context.milliseconds >= 0) s += fmt::format("  \"milliseconds\": {},\n", context.milliseconds);
  if (context.entities >= 0) s += fmt::format("  \"entities\": {},\n", context.entities);
  if (!context.procFile.empty()) {
    s += fmt::format("  \"proc\": {{\"file\": {}, \"polygonsDropped\": {}}},\n", jsonString(context.procFile),
                     models.empty() ? 0 : models.front()->stats().procPolygonsRemoved);
  }
  const ModelMemory memory = cmkitMemory(models);
  s += fmt::format(
      "  \"total\": {{\"models\": {}, {}, \"cmkitArrayBytes\": {}, \"cmkitQueryDataBytes\": {}}},\n",
      models.size(), countsJson(total), memory.arrays, memory.queryData);
  s += "  \"models\": [\n" + modelsJson + (modelsJson.empty() ? "" : "\n") + "  ]\n}\n";
  return s;
}

}  // namespace cmkit::cli
