// Pictures: the software rasteriser, PNG encoding, and `cmkit render`
// checked by decoding its PNG (stb_image) and measuring it.
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>

#include "cmkit/tools/picture.h"
#include "model_fixtures.h"
#include "test_support.h"

namespace cmkit {
namespace {

namespace fs = std::filesystem;

/// Smallest pixel variance (per channel, 0..255 scale) of a picture that
/// shows something.
constexpr double kMinVariance = 50;
/// Smallest number of distinct colours of a picture of a level.
constexpr std::size_t kMinDistinctColors = 8;

struct Decoded {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

Decoded decodePng(const fs::path& path) {
  Decoded d;
  int channels = 0;
  unsigned char* px = stbi_load(path.c_str(), &d.width, &d.height, &channels, 3);
  if (px) {
    d.rgb.assign(px, px + std::size_t(d.width) * std::size_t(d.height) * 3);
    stbi_image_free(px);
  }
  return d;
}

double variance(const std::vector<std::uint8_t>& bytes) {
  if (bytes.empty()) return 0;
  double sum = 0, sq = 0;
  for (std::uint8_t b : bytes) {
    sum += b;
    sq += double(b) * b;
  }
  const double n = double(bytes.size());
  return sq / n - (sum / n) * (sum / n);
}

std::size_t distinctColors(const std::vector<std::uint8_t>& rgb) {
  std::set<std::uint32_t> colors;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3)
    colors.insert(std::uint32_t(rgb[i]) << 16 | std::uint32_t(rgb[i + 1]) << 8 | rgb[i + 2]);
  return colors.size();
}

/// A brushDef3 block for an axis-aligned box (test::axialBrush).
std::string boxBrush(const Vec3& mn, const Vec3& mx, const char* material) {
  return test::axialBrush(Bounds(mn, mx), material);
}

/// A closed room of six brushes with a water pool and a clip pillar.
std::string boxRoomMap() {
  const char* wall = "textures/base_wall/lfwall27d";
  std::string m = "Version 2\n{\n\"classname\" \"worldspawn\"\n";
  m += boxBrush({-512, -512, -16}, {512, 512, 0}, wall);    // floor
  m += boxBrush({-512, -512, 256}, {512, 512, 272}, wall);  // ceiling
  m += boxBrush({-528, -512, -16}, {-512, 512, 272}, wall);
  m += boxBrush({512, -512, -16}, {528, 512, 272}, wall);
  m += boxBrush({-512, -528, -16}, {512, -512, 272}, wall);
  m += boxBrush({-512, 512, -16}, {512, 528, 272}, wall);
  m += boxBrush({-200, -200, 0}, {0, 0, 48}, "textures/liquids/water");
  m += boxBrush({100, 100, 0}, {164, 164, 200}, "textures/common/player_clip");
  m += boxBrush({-400, 200, 0}, {-300, 300, 96}, wall);
  return m + "}\n";
}

/// Runs the CLI; returns its exit code (-1 when it is not built).
int runCli(const std::string& args) {
  const std::string cli = CMKIT_CLI_PATH;
  if (cli.empty()) return -1;
  return std::system(("\"" + cli + "\" " + args + " > /dev/null").c_str());
}

TEST(DebugPicture, RendersAHandBuiltModel) {
  const ModelPtr m =
      std::make_shared<const CollisionModel>(test::ModelMaker()
                                                 .addBox({{-64, -64, -64}, {64, 64, 64}})
                                                 .addBox({{100, -16, -16}, {132, 16, 16}}, contents::kWater)
                                                 .build());
  PictureOptions o;
  o.width = 160;
  o.height = 120;
  const Image img = renderPicture(std::span(&m, 1), {}, o);
  ASSERT_EQ(img.width, 160);
  ASSERT_EQ(img.height, 120);
  ASSERT_EQ(img.rgba.size(), 160u * 120u * 4u);
  std::vector<std::uint8_t> rgb;
  for (std::size_t i = 0; i < img.rgba.size(); i += 4) rgb.insert(rgb.end(), &img.rgba[i], &img.rgba[i] + 3);
  EXPECT_GT(variance(rgb), kMinVariance);
  EXPECT_GE(distinctColors(rgb), 4u);
  auto png = encodePng(img);
  ASSERT_TRUE(png);
  ASSERT_GT(png->size(), 8u);
  EXPECT_EQ((*png)[1], 'P');
}

TEST(DebugPicture, NearPlaneClipsGeometryBehindTheCamera) {
  // A camera inside a big box: the walls around and behind it must not
  // produce garbage (everything drawn is in front).
  const ModelPtr m = std::make_shared<const CollisionModel>(
      test::ModelMaker().addBox({{-512, -512, -512}, {512, 512, 512}}).build());
  PictureOptions o;
  o.width = 64;
  o.height = 48;
  Camera cam;
  cam.eye = {0, 0, 0};
  o.camera = cam;
  const Image img = renderPicture(std::span(&m, 1), {}, o);
  EXPECT_EQ(img.rgba.size(), 64u * 48u * 4u);
}

TEST(DebugPicture, OverlayDrawsOverTheGeometryThroughTheSameCamera) {
  // A top view of a box with a magenta line over its middle (above the cut:
  // the overlay is not cut) on top of the box: the pixel at the picture's
  // centre is magenta; without the overlay it is not.
  const ModelPtr m = std::make_shared<const CollisionModel>(
      test::ModelMaker().addBox({{-64, -64, -64}, {64, 64, 64}}).build());
  PictureOptions o;
  o.width = 65;
  o.height = 65;
  o.view = CameraView::TopDown;
  o.cutHeight = 0;
  const auto centre = [](const Image& img) {
    const std::size_t at =
        (std::size_t(img.height / 2) * std::size_t(img.width) + std::size_t(img.width / 2)) * 4;
    return Rgba{img.rgba[at], img.rgba[at + 1], img.rgba[at + 2], img.rgba[at + 3]};
  };
  EXPECT_NE(centre(renderPicture(std::span(&m, 1), {}, o)), colors::kMagenta);
  int calls = 0;
  o.overlay = [&](DebugDraw& draw) {
    ++calls;
    draw.line({-100, 0, 100}, {100, 0, 100}, colors::kMagenta, {DrawKind::Label});
  };
  EXPECT_EQ(centre(renderPicture(std::span(&m, 1), {}, o)), colors::kMagenta);
  EXPECT_EQ(calls, 1);
}

TEST(DebugPicture, EmptyPictureIsRejectedByTheEncoder) { EXPECT_FALSE(encodePng(Image{})); }

TEST(DebugPicture, CliRendersABoxRoomWithTraces) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the cmkit CLI is not built";
  const test::ScratchDir scratch("debug_picture_box_room");
  const fs::path& dir = scratch.path();
  std::ofstream(dir / "box_room.map") << boxRoomMap();
  std::ofstream(dir / "q.txt")
      << "translation trm=box:-16,-16,0,16,16,72 start=-300,-300,200 end=300,300,-50\n"
         "translation trm=point start=0,0,200 end=0,0,-100\n";
  ASSERT_EQ(runCli("query " + (dir / "box_room.map").string() + " " + (dir / "q.txt").string() + " -o " +
                   (dir / "r.txt").string() + " 2>/dev/null"),
            0);
  const fs::path png = dir / "room.png";
  ASSERT_EQ(
      runCli("render " + (dir / "box_room.map").string() + " --size 320x200 --queries " +
             (dir / "q.txt").string() + " --results " + (dir / "r.txt").string() + " -o " + png.string()),
      0);
  const Decoded d = decodePng(png);
  ASSERT_EQ(d.width, 320);
  ASSERT_EQ(d.height, 200);
  EXPECT_GT(variance(d.rgb), kMinVariance);
  EXPECT_GE(distinctColors(d.rgb), kMinDistinctColors);

  const fs::path top = dir / "top.png";
  ASSERT_EQ(runCli("render " + (dir / "box_room.map").string() + " --top --size 200x200 -o " + top.string()),
            0);
  const Decoded t = decodePng(top);
  ASSERT_EQ(t.width, 200);
  EXPECT_GT(variance(t.rgb), kMinVariance);
  EXPECT_GE(distinctColors(t.rgb), kMinDistinctColors);
}

TEST(DebugPicture, CliViewRemovesItsSceneFolderWhenStopped) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the cmkit CLI is not built";
  const test::ScratchDir scratch("debug_picture_view");
  const fs::path& dir = scratch.path();
  std::ofstream(dir / "box_room.map") << boxRoomMap();
  const fs::path viewer = dir / "viewer";  // a stand-in for the built viewer
  fs::create_directories(viewer);
  std::ofstream(viewer / "index.html") << "<html></html>\n";
  const fs::path out = dir / "out.txt";
  // A stale out.txt of an earlier run would be read before the new server
  // writes it (the shell opens it in the background job).
  fs::remove(out);
  // Background jobs of a non-interactive shell ignore SIGINT, so the test
  // stops the server with SIGTERM (which takes the same way out as Ctrl-C).
  std::ofstream(dir / "run.sh") << "\"" << CMKIT_CLI_PATH << "\" view \"" << (dir / "box_room.map").string()
                                << "\" --port 0 --viewer-dir \"" << viewer.string() << "\" > \""
                                << out.string() << "\" 2>&1 &\n"
                                << "pid=$!\n"
                                << "for i in $(seq 200); do grep -q '^viewer: ' \"" << out.string()
                                << "\" && break; sleep 0.05; done\n"
                                << "kill -TERM $pid\n"
                                << "wait $pid\n";
  ASSERT_EQ(std::system(("sh \"" + (dir / "run.sh").string() + "\"").c_str()), 0) << test::readFile(out);
  const std::string text = test::readFile(out);
  const auto at = text.find("scene: ");
  ASSERT_NE(at, std::string::npos) << text;
  const fs::path scene = text.substr(at + 7, text.find('\n', at) - at - 7);
  EXPECT_NE(text.find("stopping: removing " + scene.string()), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(scene)) << scene << " was left behind";
}

TEST(DebugPicture, CliRendersLt4) {
  const fs::path map = test::dataFile("maps/lt4/lt4.map");  // bundled in data/maps/lt4
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the cmkit CLI is not built";
  const test::ScratchDir scratch("debug_picture_lt4");
  const fs::path png = scratch.path() / "lt4.png";
  ASSERT_EQ(runCli("render " + map.string() + " --top --size 400x300 -o " + png.string()), 0);
  const Decoded d = decodePng(png);
  ASSERT_EQ(d.width, 400);
  ASSERT_EQ(d.height, 300);
  EXPECT_GT(variance(d.rgb), kMinVariance);
  EXPECT_GE(distinctColors(d.rgb), kMinDistinctColors);
}

TEST(DebugPicture, CliRejectsABadSize) {
  if (std::string(CMKIT_CLI_PATH).empty()) GTEST_SKIP() << "the cmkit CLI is not built";
  const test::ScratchDir scratch("debug_picture_bad_size");
  const fs::path& dir = scratch.path();
  std::ofstream(dir / "room.map") << boxRoomMap();
  EXPECT_NE(runCli("render " + (dir / "room.map").string() + " --size 12 -o " + (dir / "x.png").string() +
                   " 2>/dev/null"),
            0);
}

}  // namespace
}  // namespace cmkit
