// Wavefront OBJ + MTL export, and saveScene (export by file extension).
#include <algorithm>
#include <cstdio>
#include <fstream>

#include "cmkit/contents.h"
#include "debug/scene_collector.h"

namespace cmkit {
namespace {

using detail::Group;
using detail::GroupKind;

std::string materialName(const Group& g) {
  if (g.kind == GroupKind::Polygons) {
    std::string c = contentsToStringExact(g.contents);
    for (char& ch : c)
      if (ch == ',') ch = '+';
    return "contents_" + (c.empty() ? std::string("none") : c);
  }
  char name[32];
  std::snprintf(name, sizeof name, "line_%02x%02x%02x", g.color.r, g.color.g, g.color.b);
  return name;
}

std::string objectName(const Group& g) {
  std::string name = g.kind == GroupKind::Trace
                         ? "trace_" + std::to_string(g.trace) + "_" + std::string(toString(g.drawKind))
                         : g.model + "_" + detail::toString(g.kind) + "_" + std::to_string(g.contents);
  for (char& c : name)
    if (c == ' ') c = '_';
  return name;
}

void appendNumber(std::string& out, Real v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  out += buf;
}

void appendVec(std::string& out, const char* prefix, const Vec3& v) {
  out += prefix;
  appendNumber(out, v.x);
  out += ' ';
  appendNumber(out, v.y);
  out += ' ';
  appendNumber(out, v.z);
  out += '\n';
}

bool endsWith(const std::string& s, std::string_view suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

Status writeFile(const std::string& path, const void* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{"cannot write the file", path};
  out.write(static_cast<const char*>(data), std::streamsize(size));
  if (!out) return Error{"cannot write the file", path};
  return Ok{};
}

}  // namespace

std::string exportObj(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                      const std::string& mtlFileName, const ExportOptions& options) {
  const std::vector<Group> groups = detail::collectScene(models, traces, options);
  std::string out = "# cmkit collision models (map coordinates, z up)\nmtllib " + mtlFileName + "\n";
  std::size_t vertexBase = 1;  // OBJ indices start at 1
  std::size_t normalBase = 1;
  for (const Group& g : groups) {
    out += "o " + objectName(g) + "\nusemtl " + materialName(g) + "\n";
    for (const Vec3& p : g.positions) appendVec(out, "v ", p);
    for (const Vec3& n : g.normals) appendVec(out, "vn ", n);
    if (g.triangles) {
      for (std::size_t i = 0; i + 2 < g.indices.size(); i += 3) {
        out += 'f';
        for (int k = 0; k < 3; ++k) {
          const std::size_t v = g.indices[i + std::size_t(k)];
          out += ' ' + std::to_string(vertexBase + v) + "//" + std::to_string(normalBase + v);
        }
        out += '\n';
      }
    } else {
      for (std::size_t i = 0; i + 1 < g.indices.size(); i += 2)
        out += "l " + std::to_string(vertexBase + g.indices[i]) + ' ' +
               std::to_string(vertexBase + g.indices[i + 1]) + '\n';
    }
    vertexBase += g.positions.size();
    normalBase += g.normals.size();
  }
  return out;
}

std::string exportMtl(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                      const ExportOptions& options) {
  const std::vector<Group> groups = detail::collectScene(models, traces, options);
  std::string out = "# cmkit materials: one per contents value, one per line colour\n";
  std::vector<std::string> written;
  for (const Group& g : groups) {
    const std::string name = materialName(g);
    if (std::find(written.begin(), written.end(), name) != written.end()) continue;
    written.push_back(name);
    out += "newmtl " + name + "\nKd ";
    appendNumber(out, Real(g.color.r) / 255);
    out += ' ';
    appendNumber(out, Real(g.color.g) / 255);
    out += ' ';
    appendNumber(out, Real(g.color.b) / 255);
    out += "\nd ";
    appendNumber(out, Real(g.color.a) / 255);
    out += "\n\n";
  }
  return out;
}

Status saveScene(const std::string& path, std::span<const ModelPtr> models,
                 std::span<const TraceRecord> traces, const ExportOptions& options) {
  if (endsWith(path, ".gltf")) {
    const std::string json = exportGltf(models, traces, options);
    return writeFile(path, json.data(), json.size());
  }
  if (endsWith(path, ".glb")) {
    const std::vector<std::uint8_t> glb = exportGlb(models, traces, options);
    return writeFile(path, glb.data(), glb.size());
  }
  if (endsWith(path, ".obj")) {
    const std::string mtlPath = path.substr(0, path.size() - 4) + ".mtl";
    const std::size_t slash = mtlPath.find_last_of('/');
    const std::string mtlName = slash == std::string::npos ? mtlPath : mtlPath.substr(slash + 1);
    const std::string obj = exportObj(models, traces, mtlName, options);
    if (Status s = writeFile(path, obj.data(), obj.size()); !s) return s;
    const std::string mtl = exportMtl(models, traces, options);
    return writeFile(mtlPath, mtl.data(), mtl.size());
  }
  return Error{"unknown export format: expected .gltf, .glb or .obj", path};
}

}  // namespace cmkit
