// picture.h: pictures of collision models and traces, rendered in
// software (a z-buffered rasteriser behind the DebugDraw interface) and
// written as PNG.
//
// CONTRACT
// - World space is the map's: z up, map units.
// - Polygons are shaded by the angle of their normal to a fixed light and
//   coloured by contents (contentColor); lines are drawn 1 pixel wide with a
//   small depth bias so that edges on polygons show; text is drawn with a
//   tiny built-in vector font.
// - Nothing here is shared between calls: a PictureCanvas is one picture.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "cmkit/result.h"
#include "cmkit/tools/debug_draw.h"

namespace cmkit {

/// An RGBA picture, rows top to bottom, 4 bytes per pixel.
struct Image {
  /// Width in pixels.
  int width = 0;
  /// Height in pixels.
  int height = 0;
  /// width * height * 4 bytes, rows top to bottom.
  std::vector<std::uint8_t> rgba;
};

/// A pinhole (perspective) or orthographic camera.
struct Camera {
  /// True: pinhole camera, false: orthographic.
  bool perspective = true;
  /// Position of the camera.
  Vec3 eye;
  Vec3 forward{1, 0, 0};       ///< unit view direction
  Vec3 right{0, -1, 0};        ///< unit, screen x
  Vec3 up{0, 0, 1};            ///< unit, screen y
  Real fovYDegrees = 50;       ///< perspective: vertical field of view
  Real orthoHalfHeight = 512;  ///< orthographic: half the visible height (map units)
  Real nearDist = 1;           ///< perspective: geometry closer than this is clipped
};

/// How renderPicture frames the scene when no camera is given.
enum class CameraView {
  Perspective,  ///< from above one corner, looking down at about 35 degrees
  TopDown,      ///< orthographic, looking straight down (x right, y up)
};

/// A camera that shows all of `bounds` in a picture of the given aspect
/// ratio (width / height).
Camera frameCamera(const Bounds& bounds, CameraView view, Real aspect);

/// The software rasteriser: a DebugDraw that draws into an Image.
class PictureCanvas final : public DebugDraw {
 public:
  /// A canvas of width x height pixels filled with `background`, seen through `camera`.
  PictureCanvas(int width, int height, const Camera& camera, const Rgba& background);

  void line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag& tag) override;
  void polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
               const DrawTag& tag) override;
  void text(const Vec3& at, std::string_view text, const Rgba& color, const DrawTag& tag) override;

  /// With depth testing off, later primitives are drawn over everything
  /// (used for trace overlays).
  void setDepthTest(bool on) { depthTest_ = on; }
  /// The picture drawn so far.
  const Image& image() const { return image_; }

 private:
  struct Projected {
    Real x = 0, y = 0;  ///< pixel coordinates
    Real depthKey = 0;  ///< larger = nearer; linear in screen space
  };
  /// Camera-space (right, up, forward) coordinates of a world point.
  Vec3 toView(const Vec3& p) const;
  Projected project(const Vec3& view) const;
  void fillTriangle(const Projected& a, const Projected& b, const Projected& c, const Rgba& color);
  void plot(int x, int y, Real depthKey, const Rgba& color, bool writeDepth);

  Image image_;
  std::vector<float> depth_;
  Camera camera_;
  Real focal_ = 1;  ///< pixels per unit at distance 1 (perspective) or per map unit (ortho)
  bool depthTest_ = true;
};

/// Options of renderPicture.
struct PictureOptions {
  /// Width of the picture in pixels.
  int width = 1024;
  /// Height of the picture in pixels.
  int height = 768;
  /// Where the camera is put when `camera` is empty.
  CameraView view = CameraView::Perspective;
  /// The camera; when absent, frameCamera() on the models' bounds.
  std::optional<Camera> camera;
  /// Draw polygon edges over the filled polygons.
  bool wireframe = true;
  /// Also draw internal edges (green).
  bool internalEdges = false;
  /// Only polygons with these contents.
  std::uint32_t contentMask = contents::kMaskAll;
  /// Clip away everything above this height (world z), to look into rooms
  /// from above. When absent: for the top-down view, the top
  /// kAutoCutFraction of the scene's height is cut away.
  std::optional<Real> cutHeight;
  /// Where each model is placed (index = model index); models past the end
  /// are at the origin with identity axis.
  std::vector<Placement> placements;
  /// Draw traces over the geometry, ignoring depth.
  bool tracesOnTop = true;
  /// Colour of the empty background.
  Rgba background{28, 30, 36, 255};
  /// The caller's own drawing (paths, markers, labels), called once after
  /// the traces with the picture's canvas: seen through the same camera,
  /// over the geometry when tracesOnTop, and not cut by cutHeight. Empty:
  /// nothing.
  std::function<void(DebugDraw&)> overlay;
};

/// Fraction of the scene height that the automatic top-down cut removes.
inline constexpr Real kAutoCutFraction = 0.2f;

/// Renders the models (placed by options.placements) and the traces of
/// `traces` into a picture.
Image renderPicture(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                    const PictureOptions& options);

/// The PNG encoding of a picture (stb_image_write).
Result<std::vector<std::uint8_t>> encodePng(const Image& image);

/// Writes a picture as a PNG file.
Status savePng(const std::string& path, const Image& image);

}  // namespace cmkit
