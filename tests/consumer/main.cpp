// Uses the installed cmkit package: builds a box trace model and checks it.
#include <cmkit/contents.h>
#include <cmkit/trace_model.h>

#include <cstdio>

int main() {
  auto box = cmkit::TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  if (!box.ok()) {
    std::fprintf(stderr, "box failed: %s\n", box.error().toString().c_str());
    return 1;
  }
  auto solid = cmkit::contentsFromString("solid,playerclip");
  if (!solid.ok() || *solid != (cmkit::contents::kSolid | cmkit::contents::kPlayerClip)) return 1;
  std::printf("consumer ok: box with %d vertices, %d edges, %d polygons\n", box->numVertices(),
              box->numEdges(), box->numPolygons());
  return box->numVertices() == 8 && box->numEdges() == 12 && box->numPolygons() == 6 ? 0 : 1;
}
