// Reading .cm files (the original's LoadCollisionModelFile and its Parse*
// functions): see cm_file.h for what is accepted and what a model holds
// after loading.
#include <limits>
#include <new>
#include <unordered_map>

#include "cmkit/cm_file.h"
#include "cmkit/contents.h"
#include "cmkit/text_file.h"
#include "model/edge_normals.h"
#include "model/material_cache.h"
#include "model/model_access.h"
#include "model/tree_filter.h"
#include "text/cm_cursor.h"

namespace cmkit {

namespace {

/// readCmFileCrc reads at most this much of the file: the header is at its
/// start (comments before it may push it a little down).
constexpr std::size_t kCrcHeadBytes = 4096;

using detail::CmCursor;

constexpr std::int64_t kMaxInt = std::numeric_limits<std::int32_t>::max();
// Counts read from the file are trusted for reserving only up to this; the
// vectors grow beyond it as records are actually read.
constexpr std::int64_t kMaxReserve = 1 << 20;
constexpr std::string_view kSections[5] = {"vertices", "edges", "nodes", "polygons", "brushes"};

// One model being read: the model plus the file offsets of its records, for
// messages about references that can only be checked once every section has
// been read.
struct ModelReader {
  CmCursor& in;
  detail::MaterialCache& materialCache;
  ModelArrays model;
  std::unordered_map<std::string, std::int32_t> materialIndex;
  std::vector<std::size_t> edgeOffsets;     // per edge
  std::vector<std::size_t> polygonOffsets;  // per polygon
  bool seen[5] = {false, false, false, false, false};

  void vec3(Vec3& v, std::string_view what) {
    in.expectPunct('(', what);
    v.x = in.expectFloat(what);
    v.y = in.expectFloat(what);
    v.z = in.expectFloat(what);
    in.expectPunct(')', what);
  }

  void parseVertices() {
    in.expectPunct('{', "after 'vertices'");
    const std::int64_t n = in.expectInt("number of vertices", 0, kMaxInt);
    model.vertices.reserve(std::size_t(std::min(n, kMaxReserve)));
    for (std::int64_t i = 0; i < n; ++i) {
      Vec3 v;
      vec3(v, "in a vertex");
      model.vertices.push_back(v);
    }
    in.expectPunct('}', "after the vertices (is the vertex count right?)");
  }

  void parseEdges() {
    in.expectPunct('{', "after 'edges'");
    const std::int64_t n = in.expectInt("number of edges", 0, kMaxInt);
    model.edges.reserve(std::size_t(std::min(n, kMaxReserve)));
    edgeOffsets.reserve(model.edges.capacity());
    for (std::int64_t i = 0; i < n; ++i) {
      CmEdge e;
      edgeOffsets.push_back(in.tokenOffset());
      in.expectPunct('(', "before an edge's vertex numbers");
      e.vertex[0] = std::int32_t(in.expectInt("edge vertex number", 0, kMaxInt));
      e.vertex[1] = std::int32_t(in.expectInt("edge vertex number", 0, kMaxInt));
      in.expectPunct(')', "after an edge's vertex numbers");
      e.internal = in.expectInt("edge 'internal' flag", 0, 1) != 0;
      e.numUsers = std::uint8_t(in.expectInt("edge user count", 0, 255));
      model.edges.push_back(e);
    }
    in.expectPunct('}', "after the edges (is the edge count right?)");
  }

  // The tree, in pre-order with the front child first; read without
  // recursion so that a deep (or hostile) tree cannot exhaust the stack.
  void parseNodes() {
    in.expectPunct('{', "after 'nodes'");
    struct Open {
      std::int32_t node;
      int filled;
    };
    std::vector<Open> open;
    do {
      if (model.nodes.size() >= std::size_t(kMaxInt)) in.fail("too many nodes");
      CmNode node;
      in.expectPunct('(', "before a node");
      node.planeType = std::int8_t(in.expectInt("node plane type", -1, 2));
      node.planeDist = in.expectFloat("node plane distance");
      in.expectPunct(')', "after a node");
      const auto index = std::int32_t(model.nodes.size());
      if (!open.empty()) {
        Open& parent = open.back();
        node.parent = parent.node;
        model.nodes[std::size_t(parent.node)].children[parent.filled++] = index;
        if (parent.filled == 2) open.pop_back();
      }
      model.nodes.push_back(node);
      if (!model.nodes.back().isLeaf()) open.push_back({index, 0});
    } while (!open.empty());
    in.expectPunct('}', "after the node tree");
  }

  std::int32_t materialFor(std::string_view name, std::uint32_t& contents) {
    const detail::MaterialCache::Material& m = materialCache.get(name);
    contents = m.info.contents;
    auto [it, added] = materialIndex.try_emplace(m.name, std::int32_t(model.materials.size()));
    if (added) model.materials.push_back(m.name);
    return it->second;
  }

  void parsePolygons() {
    if (in.atUnsignedNumber())
      (void)in.expectInt("polygon memory hint", 0, std::numeric_limits<std::int64_t>::max() / 2);
    in.expectPunct('{', "after 'polygons'");
    while (!in.acceptPunct('}')) {
      if (!in.more()) in.fail("unexpected end of file in the polygons (missing '}')");
      polygonOffsets.push_back(in.tokenOffset());
      const std::int64_t numEdges = in.expectInt("number of polygon edges", 3, kMaxInt);
      CmPolygon p;
      p.firstEdge = std::uint32_t(model.polygonEdges.size());
      p.numEdges = std::uint32_t(numEdges);
      in.expectPunct('(', "before a polygon's edge numbers");
      for (std::int64_t i = 0; i < numEdges; ++i) {
        model.polygonEdges.push_back(std::int32_t(in.expectInt("polygon edge number", -kMaxInt, kMaxInt)));
      }
      in.expectPunct(')', "after a polygon's edge numbers (is the edge count right?)");
      vec3(p.plane.normal, "in a polygon normal");
      p.plane.dist = in.expectFloat("polygon plane distance");
      vec3(p.bounds.min, "in a polygon's bounds");
      vec3(p.bounds.max, "in a polygon's bounds");
      const std::string_view material = in.expectString("the polygon's material name (a quoted string)");
      p.material = materialFor(material, p.contents);
      model.polygons.push_back(p);
    }
  }

  void parseBrushes() {
    if (in.atUnsignedNumber())
      (void)in.expectInt("brush memory hint", 0, std::numeric_limits<std::int64_t>::max() / 2);
    in.expectPunct('{', "after 'brushes'");
    while (!in.acceptPunct('}')) {
      if (!in.more()) in.fail("unexpected end of file in the brushes (missing '}')");
      const std::int64_t numPlanes = in.expectInt("number of brush planes", 0, kMaxInt);
      CmBrush b;
      b.firstPlane = std::uint32_t(model.brushPlanes.size());
      b.numPlanes = std::uint32_t(numPlanes);
      in.expectPunct('{', "before a brush's planes");
      for (std::int64_t i = 0; i < numPlanes; ++i) {
        Plane plane;
        vec3(plane.normal, "in a brush plane normal");
        plane.dist = in.expectFloat("brush plane distance");
        model.brushPlanes.push_back(plane);
      }
      in.expectPunct('}', "after a brush's planes (is the plane count right?)");
      vec3(b.bounds.min, "in a brush's bounds");
      vec3(b.bounds.max, "in a brush's bounds");
      if (in.atUnsignedNumber()) {
        b.contents =
            std::uint32_t(in.expectInt("brush contents", 0, std::numeric_limits<std::uint32_t>::max()));
      } else {
        const std::size_t at = in.tokenOffset();
        const std::string_view names =
            in.expectString("the brush contents (a quoted list of names or an integer)");
        Result<std::uint32_t> flags = contentsFromString(names);
        if (!flags) in.failAt(at, flags.error().message);
        b.contents = *flags;
      }
      b.material = -1;  // the original's loader gives brushes no material
      b.primitiveNum = 0;
      model.brushes.push_back(b);
    }
  }

  // References between sections, checked once all are read.
  void checkReferences() {
    const auto numVertices = std::int64_t(model.vertices.size());
    for (std::size_t i = 1; i < model.edges.size(); ++i) {  // edge 0 is the dummy
      for (const std::int32_t v : model.edges[i].vertex) {
        if (v >= numVertices) {
          in.failAt(edgeOffsets[i], "edge " + std::to_string(i) + " references vertex " + std::to_string(v) +
                                        " but the model has " + std::to_string(numVertices) + " vertices");
        }
      }
    }
    const auto numEdges = std::int64_t(model.edges.size());
    for (std::size_t i = 0; i < model.polygons.size(); ++i) {
      for (const std::int32_t e : model.edgesOf(model.polygons[i])) {
        if (e == 0 || std::int64_t(e < 0 ? -std::int64_t(e) : e) >= numEdges) {
          in.failAt(polygonOffsets[i], "polygon " + std::to_string(i) + " uses edge " + std::to_string(e) +
                                           " but the model has edges 1.." + std::to_string(numEdges - 1));
        }
      }
      // Each edge must start where the previous one ends (the point and edge
      // tests take the edges as the polygon's outline).
      const CmPolygon& p = model.polygons[i];
      if (const std::ptrdiff_t k = model.brokenEdgeLoopAt(p); k >= 0) {
        const auto edges = model.edgesOf(p);
        const std::int32_t e = edges[std::size_t(k)];
        const std::int32_t prev = edges[k == 0 ? edges.size() - 1 : std::size_t(k) - 1];
        in.failAt(polygonOffsets[i],
                  "polygon " + std::to_string(i) + ": its edges do not form a loop (edge " +
                      std::to_string(e) + " starts at vertex " + std::to_string(model.edgeStart(e)) +
                      ", the edge before it ends at vertex " + std::to_string(model.edgeStart(-prev)) + ")");
      }
    }
  }

  void parse() {
    model.name = std::string(in.expectString("the model name (a quoted string)"));
    in.expectPunct('{', "after the model name");
    while (!in.acceptPunct('}')) {
      if (!in.more())
        in.fail("unexpected end of file in collisionModel \"" + model.name + "\" (missing '}')");
      const std::size_t at = in.tokenOffset();
      const std::string_view word = in.readName();
      int section = -1;
      for (int k = 0; k < 5; ++k)
        if (word == kSections[k]) section = k;
      if (section < 0) {
        in.failAt(at, "expected a section (vertices, edges, nodes, polygons, brushes) or '}', found '" +
                          std::string(word.empty() ? std::string_view("?") : word) + "'");
      }
      if (seen[section]) in.failAt(at, "repeated '" + std::string(word) + "' section");
      seen[section] = true;
      switch (section) {
        case 0:
          parseVertices();
          break;
        case 1:
          parseEdges();
          break;
        case 2:
          parseNodes();
          break;
        case 3:
          parsePolygons();
          break;
        default:
          parseBrushes();
          break;
      }
    }
    checkReferences();
    // What the original does after reading a model.
    detail::filterItemsIntoTree(model);
    model.stats.sharpEdges = detail::computeEdgeNormals(model);
    for (std::size_t i = 1; i < model.edges.size(); ++i) model.stats.internalEdges += model.edges[i].internal;
    detail::computeModelBoundsAndContents(model);
  }
};

// The header: "CM", the version "1.00" and the map CRC (returned).
std::uint32_t parseHeader(CmCursor& in) {
  const std::size_t at = in.tokenOffset();
  if (in.readName() != "CM") in.failAt(at, "not a .cm file: expected 'CM' at the start");
  const std::size_t versionAt = in.tokenOffset();
  if (in.expectWord("the version \"1.00\"") != "1.00")
    in.failAt(versionAt, "unsupported .cm version (only \"1.00\" is known)");
  return std::uint32_t(in.expectInt("the map CRC", 0, std::numeric_limits<std::uint32_t>::max()));
}

CmFile parseFile(CmCursor& in, const MaterialTable& materials) {
  CmFile file;
  file.crc = parseHeader(in);
  detail::MaterialCache cache(materials);
  while (in.more()) {
    const std::size_t modelAt = in.tokenOffset();
    const std::string_view word = in.readName();
    if (word != "collisionModel") {
      in.failAt(modelAt, "expected 'collisionModel' or the end of the file, found '" +
                             std::string(word.empty() ? std::string_view("?") : word) + "'");
    }
    ModelReader reader{in, cache, {}, {}, {}, {}};
    reader.parse();
    file.models.push_back(detail::ModelAccess::seal(std::move(reader.model)));
  }
  return file;
}

}  // namespace

Result<CmFile> parseCmText(std::string_view text, std::string fileName, const MaterialTable& materials) {
  CmCursor in(text);
  try {
    return parseFile(in, materials);
  } catch (const detail::SyntaxError& e) {
    return detail::toError(e, std::move(fileName));
  } catch (const std::bad_alloc&) {  // counts in the file far beyond its size
    return Error("out of memory while reading the models", std::move(fileName));
  }
}

Result<CmFile> loadCmFile(const std::string& path, const MaterialTable& materials) {
  Result<std::string> text = readTextFile(path);
  if (!text) return text.error();
  return parseCmText(*text, path, materials);
}

Result<std::uint32_t> readCmFileCrc(const std::string& path) {
  Result<std::string> head = readTextFile(path, kCrcHeadBytes);
  if (!head) return head.error();
  CmCursor in(*head);
  try {
    return parseHeader(in);
  } catch (const detail::SyntaxError& e) {
    return detail::toError(e, path);
  }
}

}  // namespace cmkit
