// debug_drawer: a custom DebugDraw that counts what the library asks it to
// draw instead of rendering it. An engine would forward these calls to its
// own debug renderer.
//
//   debug_drawer [MAP]   (default: the bundled data/maps/lt4/lt4.map)
#include <cmkit/compile.h>
#include <cmkit/map.h>
#include <cmkit/materials.h>
#include <cmkit/query.h>
#include <cmkit/tools/debug_draw.h>

#include <array>
#include <cstdio>
#include <string>

namespace {

// Counts lines, polygons and labels per DrawKind.
class CountingDraw final : public cmkit::DebugDraw {
 public:
  void line(const cmkit::Vec3&, const cmkit::Vec3&, const cmkit::Rgba&, const cmkit::DrawTag& tag) override {
    ++lines[std::size_t(tag.kind)];
  }
  void polygon(std::span<const cmkit::Vec3> points, const cmkit::Vec3&, const cmkit::Rgba&,
               const cmkit::DrawTag& tag) override {
    ++polygons[std::size_t(tag.kind)];
    corners += points.size();
  }
  void text(const cmkit::Vec3&, std::string_view, const cmkit::Rgba&, const cmkit::DrawTag& tag) override {
    ++labels[std::size_t(tag.kind)];
  }

  void print(const char* what) const {
    std::printf("%s:\n", what);
    for (std::size_t k = 0; k < lines.size(); ++k) {
      if (lines[k] + polygons[k] + labels[k] == 0) continue;
      std::printf("  %-15s %6zu lines %6zu polygons %3zu labels\n",
                  std::string(cmkit::toString(cmkit::DrawKind(k))).c_str(), lines[k], polygons[k], labels[k]);
    }
  }

  static constexpr std::size_t kKinds = std::size_t(cmkit::DrawKind::Label) + 1;
  std::array<std::size_t, kKinds> lines{}, polygons{}, labels{};
  std::size_t corners = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : CMKIT_EXAMPLE_MAP;
  auto map = cmkit::loadMapFile(path);
  if (!map) {
    std::fprintf(stderr, "debug_drawer: %s\n", map.error().toString().c_str());
    return 1;
  }
  auto built = cmkit::buildCollisionModels(*map, cmkit::MaterialTable{});
  if (!built || built->models.empty()) {
    std::fprintf(stderr, "debug_drawer: %s\n",
                 built ? "the map has no models" : built.error().toString().c_str());
    return 1;
  }
  const std::vector<cmkit::ModelPtr>& models = built->models;  // built->warnings: what the build skipped
  const cmkit::CollisionModel& world = *models[0];

  // The world's polygons within 512 units of a viewer, filled, with normals.
  CountingDraw modelDraw;
  cmkit::DrawOptions options;
  options.filled = true;
  options.normals = true;
  options.viewOrigin = {1548, -734, -80};
  options.radius = 512;
  cmkit::drawModel(modelDraw, world, cmkit::Placement{}, options);
  modelDraw.print("world within 512 units of the viewer");
  std::printf("  (%zu polygon corners)\n", modelDraw.corners);

  // One trace: a player box dropped onto the floor.
  auto box = cmkit::TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  if (!box) {
    std::fprintf(stderr, "debug_drawer: %s\n", box.error().toString().c_str());
    return 1;
  }
  cmkit::QueryWork work;
  cmkit::TranslationQuery q;
  q.trm = &*box;
  q.start = {1548, -734, -144};
  q.end = {1548, -734, -656};
  cmkit::TraceDrawing trace;
  trace.trm = q.trm;
  trace.start = q.start;
  trace.end = q.end;
  trace.result = cmkit::translate(world, q, work);
  if (trace.result.status != cmkit::QueryStatus::Ok) {
    std::fprintf(stderr, "debug_drawer: query refused: %s\n", cmkit::toString(trace.result.status));
    return 1;
  }
  CountingDraw traceDraw;
  cmkit::drawTrace(traceDraw, trace);
  traceDraw.print("one trace");
  return 0;
}
