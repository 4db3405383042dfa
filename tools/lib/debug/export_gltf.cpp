// glTF 2.0 export (.gltf with an embedded base64 buffer, or .glb) of the
// groups collected by collectScene.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>

#include "cmkit/contents.h"
#include "cmkit/tools/query_format.h"
#include "debug/scene_collector.h"

namespace cmkit {
namespace {

using detail::Group;
using detail::GroupKind;

// glTF constants (glTF 2.0 specification, section 5).
constexpr int kComponentFloat = 5126;
constexpr int kComponentUnsignedInt = 5125;
constexpr int kTargetArrayBuffer = 34962;
constexpr int kTargetElementArrayBuffer = 34963;
constexpr int kModeLines = 1;
constexpr int kModeTriangles = 4;
/// GLB header and chunk identifiers.
constexpr std::uint32_t kGlbMagic = 0x46546C67;  // "glTF"
constexpr std::uint32_t kGlbVersion = 2;
constexpr std::uint32_t kChunkJson = 0x4E4F534A;  // "JSON"
constexpr std::uint32_t kChunkBin = 0x004E4942;   // "BIN\0"
/// -90 degrees about x as a quaternion (x, y, z, w): z-up map space to
/// glTF's y-up.
constexpr double kZUpToYUp[4] = {-0.70710678118654752, 0, 0, 0.70710678118654752};
/// sRGB to linear exponent for material colours (glTF factors are linear).
constexpr double kSrgbGamma = 2.2;

/// Appends JSON text.
class Json {
 public:
  std::string out;
  void raw(std::string_view s) { out += s; }
  void str(std::string_view s) {
    out += '"';
    for (const char c : s) {
      if (c == '"' || c == '\\') {
        out += '\\';
        out += c;
      } else if (static_cast<unsigned char>(c) < 0x20) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\u%04x", unsigned(static_cast<unsigned char>(c)));
        out += buf;
      } else {
        out += c;
      }
    }
    out += '"';
  }
  void num(double v) {
    if (!std::isfinite(v)) v = 0;  // JSON has no Inf/NaN
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    out += buf;
  }
  void vec(const Vec3& v) {
    out += '[';
    num(v.x);
    out += ',';
    num(v.y);
    out += ',';
    num(v.z);
    out += ']';
  }
  void key(std::string_view k) {
    str(k);
    out += ':';
  }
};

void appendFloats(std::vector<std::uint8_t>& bin, const std::vector<Vec3>& vs) {
  for (const Vec3& v : vs) {
    const float f[3] = {float(v.x), float(v.y), float(v.z)};
    const auto* b = reinterpret_cast<const std::uint8_t*>(f);
    bin.insert(bin.end(), b, b + sizeof f);
  }
}

void appendU32(std::vector<std::uint8_t>& bin, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bin.push_back(std::uint8_t(v >> (8 * i)));
}

std::string base64(const std::vector<std::uint8_t>& data) {
  constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((data.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < data.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(data[i]) << 16 |
                            (i + 1 < data.size() ? std::uint32_t(data[i + 1]) << 8 : 0) |
                            (i + 2 < data.size() ? std::uint32_t(data[i + 2]) : 0);
    out += kAlphabet[(n >> 18) & 63];
    out += kAlphabet[(n >> 12) & 63];
    out += i + 1 < data.size() ? kAlphabet[(n >> 6) & 63] : '=';
    out += i + 2 < data.size() ? kAlphabet[n & 63] : '=';
  }
  return out;
}

std::string groupName(const Group& g) {
  if (g.kind == GroupKind::Trace)
    return "trace " + std::to_string(g.trace) + " " + std::string(toString(g.drawKind));
  std::string name = g.model + " " + detail::toString(g.kind);
  if (g.kind == GroupKind::Polygons) {
    const std::string c = contentsToStringExact(g.contents);
    name += " " + (c.empty() ? std::string("none") : c);
  }
  return name;
}

/// The glTF JSON (without the buffer's uri) and the binary buffer.
struct Document {
  std::string json;
  std::vector<std::uint8_t> bin;
};

Document buildDocument(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                       const ExportOptions& options, bool embedBuffer) {
  const std::vector<Group> groups = detail::collectScene(models, traces, options);
  Document doc;
  Json accessors, views, meshes, materials, nodes;
  int numAccessors = 0, numViews = 0, numMaterials = 0;
  std::map<std::uint32_t, int> polygonMaterial;  // contents -> material
  std::map<std::uint32_t, int> lineMaterial;     // packed rgba -> material

  auto addView = [&](std::size_t offset, std::size_t length, int target) {
    if (numViews++) views.raw(",");
    views.raw("{\"buffer\":0,\"byteOffset\":" + std::to_string(offset) +
              ",\"byteLength\":" + std::to_string(length) + ",\"target\":" + std::to_string(target) + "}");
    return numViews - 1;
  };
  auto addAccessor = [&](int view, int componentType, std::size_t count, const char* type,
                         const Bounds* bounds) {
    if (numAccessors++) accessors.raw(",");
    accessors.raw("{\"bufferView\":" + std::to_string(view) +
                  ",\"componentType\":" + std::to_string(componentType) +
                  ",\"count\":" + std::to_string(count) + ",\"type\":\"" + type + "\"");
    if (bounds) {
      accessors.raw(",\"min\":");
      accessors.vec(bounds->min);
      accessors.raw(",\"max\":");
      accessors.vec(bounds->max);
    }
    accessors.raw("}");
    return numAccessors - 1;
  };
  auto addMaterial = [&](const std::string& name, const Rgba& c) {
    if (numMaterials++) materials.raw(",");
    materials.raw("{\"name\":");
    materials.str(name);
    materials.raw(",\"pbrMetallicRoughness\":{\"baseColorFactor\":[");
    materials.num(std::pow(c.r / 255.0, kSrgbGamma));
    materials.raw(",");
    materials.num(std::pow(c.g / 255.0, kSrgbGamma));
    materials.raw(",");
    materials.num(std::pow(c.b / 255.0, kSrgbGamma));
    materials.raw(",");
    materials.num(c.a / 255.0);
    materials.raw("],\"metallicFactor\":0,\"roughnessFactor\":1},\"doubleSided\":true");
    if (c.a < 255) materials.raw(",\"alphaMode\":\"BLEND\"");
    materials.raw("}");
    return numMaterials - 1;
  };
  auto align = [&] {
    while (doc.bin.size() % 4) doc.bin.push_back(0);
  };

  // One mesh and one node per group; trace groups become children of one
  // node per trace.
  std::vector<int> rootChildren;
  std::map<std::int32_t, std::vector<int>> traceChildren;
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const Group& g = groups[gi];
    Bounds bounds;
    for (const Vec3& p : g.positions) bounds.addPoint(p);
    align();
    std::size_t offset = doc.bin.size();
    appendFloats(doc.bin, g.positions);
    const int posAccessor = addAccessor(addView(offset, doc.bin.size() - offset, kTargetArrayBuffer),
                                        kComponentFloat, g.positions.size(), "VEC3", &bounds);
    int normalAccessor = -1;
    if (g.triangles) {
      offset = doc.bin.size();
      appendFloats(doc.bin, g.normals);
      normalAccessor = addAccessor(addView(offset, doc.bin.size() - offset, kTargetArrayBuffer),
                                   kComponentFloat, g.normals.size(), "VEC3", nullptr);
    }
    offset = doc.bin.size();
    for (std::uint32_t i : g.indices) appendU32(doc.bin, i);
    const int indexAccessor = addAccessor(addView(offset, doc.bin.size() - offset, kTargetElementArrayBuffer),
                                          kComponentUnsignedInt, g.indices.size(), "SCALAR", nullptr);
    int material;
    if (g.kind == GroupKind::Polygons) {
      auto [it, inserted] = polygonMaterial.try_emplace(g.contents, numMaterials);
      if (inserted) {
        const std::string c = contentsToStringExact(g.contents);
        addMaterial("contents " + (c.empty() ? std::string("none") : c), g.color);
      }
      material = it->second;
    } else {
      const std::uint32_t packed = std::uint32_t(g.color.r) << 24 | std::uint32_t(g.color.g) << 16 |
                                   std::uint32_t(g.color.b) << 8 | g.color.a;
      auto [it, inserted] = lineMaterial.try_emplace(packed, numMaterials);
      if (inserted) {
        char name[32];
        std::snprintf(name, sizeof name, "line #%08x", unsigned(packed));
        addMaterial(name, g.color);
      }
      material = it->second;
    }

    if (gi) meshes.raw(",");
    meshes.raw("{\"name\":");
    meshes.str(groupName(g));
    meshes.raw(",\"primitives\":[{\"attributes\":{\"POSITION\":" + std::to_string(posAccessor));
    if (normalAccessor >= 0) meshes.raw(",\"NORMAL\":" + std::to_string(normalAccessor));
    meshes.raw("},\"indices\":" + std::to_string(indexAccessor) +
               ",\"material\":" + std::to_string(material) +
               ",\"mode\":" + std::to_string(g.triangles ? kModeTriangles : kModeLines) + "}]}");

    // Node for the group (node 0 is the root, written last).
    const int node = int(gi) + 1;
    nodes.raw(",{\"name\":");
    nodes.str(groupName(g));
    nodes.raw(",\"mesh\":" + std::to_string(gi) + ",\"extras\":{\"kind\":");
    nodes.str(detail::toString(g.kind));
    if (g.kind == GroupKind::Trace) {
      nodes.raw(",\"trace\":" + std::to_string(g.trace) + ",\"part\":");
      nodes.str(toString(g.drawKind));
      traceChildren[g.trace].push_back(node);
    } else {
      nodes.raw(",\"model\":");
      nodes.str(g.model);
      nodes.raw(",\"modelIndex\":" + std::to_string(g.modelIndex));
      const auto at = std::size_t(g.modelIndex);
      if (at < options.classNames.size() && !options.classNames[at].empty()) {
        nodes.raw(",\"classname\":");
        nodes.str(options.classNames[at]);
      }
      if (at < options.placements.size()) {
        nodes.raw(",\"origin\":");
        nodes.vec(options.placements[at].origin);
      }
      nodes.raw(",\"contents\":" + std::to_string(g.contents) + ",\"contentsNames\":");
      nodes.str(contentsToStringExact(g.contents));
      rootChildren.push_back(node);
    }
    nodes.raw("}}");
  }
  // One node per trace holding its parts, with the query and result.
  int nextNode = int(groups.size()) + 1;
  for (const auto& [trace, children] : traceChildren) {
    const TraceRecord& r = traces[std::size_t(trace)];
    nodes.raw(",{\"name\":\"trace " + std::to_string(trace) + "\",\"children\":[");
    for (std::size_t i = 0; i < children.size(); ++i) nodes.raw((i ? "," : "") + std::to_string(children[i]));
    nodes.raw("],\"extras\":{\"kind\":\"trace\",\"trace\":" + std::to_string(trace) + ",\"query\":");
    nodes.str(r.queryLine);
    nodes.raw(",\"result\":");
    nodes.str(r.resultLine);
    nodes.raw(",\"fraction\":");
    nodes.num(r.result.fraction);
    nodes.raw(",\"endpos\":");
    nodes.vec(r.result.endPos);
    nodes.raw(",\"type\":");
    nodes.str(toString(r.result.contact.type));
    nodes.raw(",\"point\":");
    nodes.vec(r.result.contact.point);
    nodes.raw(",\"normal\":");
    nodes.vec(r.result.contact.normal);
    nodes.raw(",\"contents\":" + std::to_string(r.result.contact.contents) +
              ",\"modelFeature\":" + std::to_string(r.result.contact.modelFeature) +
              ",\"trmFeature\":" + std::to_string(r.result.contact.trmFeature));
    if (!r.entity.empty()) {
      nodes.raw(",\"entity\":");
      nodes.str(r.entity);
    }
    nodes.raw("}}");
    rootChildren.push_back(nextNode++);
  }
  align();

  Json j;
  j.raw("{\"asset\":{\"version\":\"2.0\",\"generator\":\"cmkit\"},\"scene\":0,");
  j.raw("\"scenes\":[{\"name\":\"cmkit\",\"nodes\":[0]}],\"nodes\":[{\"name\":\"cmkit\",\"rotation\":[");
  for (int i = 0; i < 4; ++i) {
    if (i) j.raw(",");
    j.num(kZUpToYUp[i]);
  }
  j.raw("],\"children\":[");
  for (std::size_t i = 0; i < rootChildren.size(); ++i)
    j.raw((i ? "," : "") + std::to_string(rootChildren[i]));
  j.raw("],\"extras\":{\"up\":\"z\",\"units\":\"map units\"}}");
  j.raw(nodes.out);
  j.raw("]");
  if (!groups.empty()) {
    j.raw(",\"meshes\":[" + meshes.out + "],\"materials\":[" + materials.out + "],\"accessors\":[" +
          accessors.out + "],\"bufferViews\":[" + views.out + "]");
    j.raw(",\"buffers\":[{\"byteLength\":" + std::to_string(doc.bin.size()));
    if (embedBuffer) j.raw(",\"uri\":\"data:application/octet-stream;base64," + base64(doc.bin) + "\"");
    j.raw("}]");
  }
  j.raw("}");
  doc.json = std::move(j.out);
  return doc;
}

}  // namespace

std::string exportGltf(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                       const ExportOptions& options) {
  return buildDocument(models, traces, options, true).json;
}

std::vector<std::uint8_t> exportGlb(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                                    const ExportOptions& options) {
  Document doc = buildDocument(models, traces, options, false);
  while (doc.json.size() % 4) doc.json += ' ';  // chunks are 4-byte aligned
  const bool hasBin = !doc.bin.empty();
  const std::size_t total = 12 + 8 + doc.json.size() + (hasBin ? 8 + doc.bin.size() : 0);
  std::vector<std::uint8_t> out;
  out.reserve(total);
  appendU32(out, kGlbMagic);
  appendU32(out, kGlbVersion);
  appendU32(out, std::uint32_t(total));
  appendU32(out, std::uint32_t(doc.json.size()));
  appendU32(out, kChunkJson);
  out.insert(out.end(), doc.json.begin(), doc.json.end());
  if (hasBin) {
    appendU32(out, std::uint32_t(doc.bin.size()));
    appendU32(out, kChunkBin);
    out.insert(out.end(), doc.bin.begin(), doc.bin.end());
  }
  return out;
}

}  // namespace cmkit
