// Writing .cm files (the original's WriteCollisionModelsToFile): the exact
// text the original writes, see cm_file.h.
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <new>
#include <thread>

#include "cmkit/cm_file.h"
#include "cmkit/contents.h"

namespace cmkit {

namespace {

// Sizes of the original's 64-bit structs, for the memory-size hints: a
// polygon is 60 bytes plus 4 per edge (cm_polygon_t with its first edge
// inline), a brush 48 bytes plus 16 per plane.
constexpr std::size_t kPolygonBaseBytes = 60;
constexpr std::size_t kPolygonEdgeBytes = 4;
constexpr std::size_t kBrushBaseBytes = 48;
constexpr std::size_t kBrushPlaneBytes = 16;

// The content flags the original can name in a .cm file: all named flags but
// projectile and renderModel, in bit order.
bool writableContentFlag(std::uint32_t flag) {
  return flag != contents::kProjectile && flag != contents::kRenderModel;
}

class CmWriter {
 public:
  explicit CmWriter(std::string& out) : out_(out) {}

  void text(std::string_view s) { out_ += s; }
  void integer(long long v) {
    char buf[24];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    out_.append(buf, r.ptr);
  }
  void number(float v) { appendCmFloat(v); }
  void vec3(const Vec3& v) {
    text("( ");
    number(v.x);
    text(" ");
    number(v.y);
    text(" ");
    number(v.z);
    text(" )");
  }

  // "%f" as the original's WriteFloatString prints it: 10 decimals, then
  // trailing zeros and a trailing dot removed.
  void appendCmFloat(float v) {
    char buf[400];  // the widest float, FLT_MAX, has 39 digits before the point
    const auto r = std::to_chars(buf, buf + sizeof buf, double(v), std::chars_format::fixed, 10);
    char* end = r.ptr;
    bool hasPoint = false;
    for (char* p = buf; p != end; ++p) hasPoint |= *p == '.';
    if (hasPoint) {
      while (end > buf && end[-1] == '0') --end;
      if (end > buf && end[-1] == '.') --end;
    }
    out_.append(buf, end);
  }

  void model(const CollisionModel& m, const CmWriteOptions& options) {
    text("collisionModel \"");
    text(m.name());
    text("\" {\n");
    vertices(m);
    edges(m);
    nodes(m);
    polygons(m, options);
    brushes(m, options);
    text("}\n");
  }

 private:
  void vertices(const CollisionModel& m) {
    text("\tvertices { /* numVertices = */ ");
    integer(static_cast<long long>(m.vertices().size()));
    text("\n");
    for (std::size_t i = 0; i < m.vertices().size(); ++i) {
      text("\t/* ");
      integer(static_cast<long long>(i));
      text(" */ ");
      vec3(m.vertices()[i]);
      text("\n");
    }
    text("\t}\n");
  }

  void edges(const CollisionModel& m) {
    // A model without edges still gets the dummy edge 0, as every model of
    // the original has it.
    const std::size_t n = m.edges().empty() ? 1 : m.edges().size();
    text("\tedges { /* numEdges = */ ");
    integer(static_cast<long long>(n));
    text("\n");
    for (std::size_t i = 0; i < n; ++i) {
      const CmEdge e = m.edges().empty() ? CmEdge{} : m.edges()[i];
      text("\t/* ");
      integer(static_cast<long long>(i));
      text(" */ ( ");
      integer(e.vertex[0]);
      text(" ");
      integer(e.vertex[1]);
      text(" ) ");
      integer(e.internal ? 1 : 0);
      text(" ");
      integer(e.numUsers);
      text("\n");
    }
    text("\t}\n");
  }

  // Pre-order, front child first: the stored order of the nodes.
  void nodes(const CollisionModel& m) {
    text("\tnodes {\n");
    if (m.nodes().empty()) {
      text("\t( -1 0 )\n");
    } else {
      std::vector<std::int32_t> stack{0};
      while (!stack.empty()) {
        const std::int32_t n = stack.back();
        stack.pop_back();
        const CmNode& node = m.nodes()[std::size_t(n)];
        text("\t( ");
        integer(node.planeType);
        text(" ");
        number(node.planeDist);
        text(" )\n");
        if (!node.isLeaf()) {
          stack.push_back(node.children[1]);
          stack.push_back(node.children[0]);
        }
      }
    }
    text("\t}\n");
  }

  void polygons(const CollisionModel& m, const CmWriteOptions& options) {
    text("\tpolygons ");
    if (options.memoryHints) {
      std::size_t bytes = 0;
      for (const CmPolygon& p : m.polygons()) bytes += kPolygonBaseBytes + kPolygonEdgeBytes * p.numEdges;
      text("/* polygonMemory = */ ");
      integer(static_cast<long long>(bytes));
      text(" ");
    }
    text("{\n");
    for (const CmPolygon& p : m.polygons()) {
      text("\t");
      integer(p.numEdges);
      text(" (");
      for (const std::int32_t e : m.edgesOf(p)) {
        text(" ");
        integer(e);
      }
      text(" ) ");
      vec3(p.plane.normal);
      text(" ");
      number(p.plane.dist);
      text(" ");
      vec3(p.bounds.min);
      text(" ");
      vec3(p.bounds.max);
      text(" \"");
      text(m.materialName(p.material));
      text("\"\n");
    }
    text("\t}\n");
  }

  void brushes(const CollisionModel& m, const CmWriteOptions& options) {
    text("\tbrushes ");
    if (options.memoryHints) {
      std::size_t bytes = 0;
      for (const CmBrush& b : m.brushes()) bytes += kBrushBaseBytes + kBrushPlaneBytes * b.numPlanes;
      text("/* brushMemory = */ ");
      integer(static_cast<long long>(bytes));
      text(" ");
    }
    text("{\n");
    for (const CmBrush& b : m.brushes()) {
      text("\t");
      integer(b.numPlanes);
      text(" {\n");
      for (const Plane& plane : m.planesOf(b)) {
        text("\t\t");
        vec3(plane.normal);
        text(" ");
        number(plane.dist);
        text("\n");
      }
      text("\t} ");
      vec3(b.bounds.min);
      text(" ");
      vec3(b.bounds.max);
      text(" \"");
      for (const ContentName& c : contentNames()) {
        if (!(b.contents & c.flag) || !writableContentFlag(c.flag)) continue;
        if (out_.back() != '"') text(",");
        text(c.name);
      }
      text("\"\n");
    }
    text("\t}\n");
  }

  std::string& out_;
};

std::size_t estimateSize(std::span<const ModelPtr> models) {
  std::size_t n = 64;
  for (const ModelPtr& m : models) {
    if (!m) continue;
    n += 40 * m->vertices().size() + 32 * m->edges().size() + 16 * m->nodes().size() +
         200 * m->polygons().size() + 16 * m->polygonEdges().size() + 64 * m->brushes().size() +
         48 * m->brushPlanes().size();
  }
  return n;
}

}  // namespace

std::string formatCmFloat(float value) {
  std::string s;
  CmWriter(s).appendCmFloat(value);
  return s;
}

std::string writeCmText(std::span<const ModelPtr> models, std::uint32_t crc, const CmWriteOptions& options) {
  std::string out;
  out.reserve(estimateSize(models));
  CmWriter w(out);
  w.text("CM \"1.00\"\n\n");
  w.integer(crc);
  w.text("\n\n");
  for (const ModelPtr& m : models) {
    if (m) w.model(*m, options);
  }
  return out;
}

Status saveCmFile(const std::string& path, std::span<const ModelPtr> models, std::uint32_t crc,
                  const CmWriteOptions& options) {
  std::string text;
  try {
    text = writeCmText(models, crc, options);
  } catch (const std::bad_alloc&) {
    return Error("out of memory while writing the models (nothing written)", path);
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return Error("is a directory, not a file", path);
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
    // Not a file (/dev/null, a pipe): written in place, never replaced.
    std::ofstream out(path, std::ios::binary);
    if (!out) return Error("cannot open for writing", path);
    out.write(text.data(), std::streamsize(text.size()));
    out.close();
    return out ? Status(Ok{}) : Status(Error("cannot write", path));
  }
  // Written beside the target and renamed over it: a failed write leaves
  // any earlier file as it was and no partial file behind.
  // The temporary name is unique among concurrent calls of this process (the
  // thread and this call's stack frame), with no shared counter.
  const std::string tmp = path + ".tmp-" +
                          std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()) % 100000) +
                          "-" + std::to_string(reinterpret_cast<std::uintptr_t>(&text) % 1000000);
  std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
  if (!f) return Error("cannot create the file", path);
  f.write(text.data(), std::streamsize(text.size()));
  f.close();
  if (!f) {
    std::filesystem::remove(tmp, ec);
    return Error("cannot write the file", path);
  }
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return Error("cannot replace the file (" + ec.message() + ")", path);
  }
  return Ok{};
}

}  // namespace cmkit
