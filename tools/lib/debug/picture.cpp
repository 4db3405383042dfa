// The software rasteriser behind PictureCanvas, camera framing and
// renderPicture (models filled and shaded, edges, traces overlaid).
#include <stb/stb_easy_font.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>

#include "cmkit/tools/picture.h"

namespace cmkit {
namespace {

/// Direction towards the light used for shading (world space, z up).
constexpr Vec3 kLightDirection{0.35f, 0.5f, 0.8f};
/// Brightness of a polygon facing away from the light.
constexpr Real kAmbient = 0.35f;
/// Brightness added by direct light.
constexpr Real kDiffuse = 0.65f;
/// Polygons seen from behind are darkened by this factor.
constexpr Real kBackFaceDim = 0.55f;
/// Lines win depth ties against polygons they lie on by this relative margin.
constexpr Real kLineDepthBias = 0.002f;
/// Perspective framing: the camera looks down by this angle (degrees)...
constexpr Real kFramePitchDegrees = 35;
/// ...from this compass direction (degrees, 0 = +x, counter-clockwise).
constexpr Real kFrameYawDegrees = 225;
/// Framing leaves this much margin around the scene (fraction of its size).
constexpr Real kFrameMargin = 1.08f;
/// Text: pixels per stb_easy_font unit.
constexpr Real kTextScale = 1.5f;
/// Bytes of vertex buffer stb_easy_font may fill per label.
constexpr std::size_t kTextBufferBytes = 64 * 1024;
/// Size of one stb_easy_font vertex (x, y, z floats + 4 colour bytes).
constexpr std::size_t kTextVertexBytes = 16;
/// Depth key meaning "farther than anything" in the z-buffer.
constexpr float kFarthest = -1e30f;

Real edgeFunction(Real ax, Real ay, Real bx, Real by, Real px, Real py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

std::uint8_t toByte(Real v) { return std::uint8_t(std::clamp(v, Real(0), Real(255)) + Real(0.5)); }

Rgba shade(const Rgba& c, Real factor) {
  return {toByte(Real(c.r) * factor), toByte(Real(c.g) * factor), toByte(Real(c.b) * factor), c.a};
}

}  // namespace

Camera frameCamera(const Bounds& bounds, CameraView view, Real aspect) {
  Camera cam;
  const Vec3 center = bounds.center();
  const Vec3 size = bounds.size();
  if (view == CameraView::TopDown) {
    cam.perspective = false;
    cam.forward = {0, 0, -1};
    cam.right = {1, 0, 0};
    cam.up = {0, 1, 0};
    cam.eye = center + Vec3{0, 0, size.z + 1};
    cam.orthoHalfHeight = std::max(size.y * Real(0.5), size.x * Real(0.5) / std::max(aspect, Real(1e-3)));
    cam.orthoHalfHeight = std::max(cam.orthoHalfHeight * kFrameMargin, Real(1));
    return cam;
  }
  const Real deg = std::numbers::pi_v<Real> / 180;
  const Real pitch = kFramePitchDegrees * deg;
  const Real yaw = kFrameYawDegrees * deg;
  // Looking from the yaw direction towards the centre, down by pitch.
  cam.forward = Vec3{-std::cos(yaw) * std::cos(pitch), -std::sin(yaw) * std::cos(pitch), -std::sin(pitch)};
  cam.right = cam.forward.cross({0, 0, 1}).normalized();
  cam.up = cam.right.cross(cam.forward).normalized();
  // Distance at which the bounding sphere fits the narrower field of view.
  const Real radius = std::max(size.length() * Real(0.5), Real(1));
  const Real halfFovY = cam.fovYDegrees * deg * Real(0.5);
  const Real halfFovX = std::atan(std::tan(halfFovY) * aspect);
  const Real dist = radius * kFrameMargin / std::sin(std::min(halfFovX, halfFovY));
  cam.eye = center - cam.forward * dist;
  cam.nearDist = std::max(Real(1), dist - radius * 2);
  return cam;
}

PictureCanvas::PictureCanvas(int width, int height, const Camera& camera, const Rgba& background)
    : camera_(camera) {
  image_.width = std::max(width, 1);
  image_.height = std::max(height, 1);
  const auto pixels = std::size_t(image_.width) * std::size_t(image_.height);
  image_.rgba.resize(pixels * 4);
  for (std::size_t i = 0; i < pixels; ++i) {
    image_.rgba[i * 4 + 0] = background.r;
    image_.rgba[i * 4 + 1] = background.g;
    image_.rgba[i * 4 + 2] = background.b;
    image_.rgba[i * 4 + 3] = 255;
  }
  depth_.assign(pixels, kFarthest);
  if (camera_.perspective) {
    const Real halfFovY = camera_.fovYDegrees * std::numbers::pi_v<Real> / 360;
    focal_ = Real(image_.height) * Real(0.5) / std::tan(halfFovY);
  } else {
    focal_ = Real(image_.height) * Real(0.5) / camera_.orthoHalfHeight;
  }
}

Vec3 PictureCanvas::toView(const Vec3& p) const {
  const Vec3 d = p - camera_.eye;
  return {d.dot(camera_.right), d.dot(camera_.up), d.dot(camera_.forward)};
}

PictureCanvas::Projected PictureCanvas::project(const Vec3& v) const {
  const Real cx = Real(image_.width) * Real(0.5);
  const Real cy = Real(image_.height) * Real(0.5);
  if (camera_.perspective) {
    const Real inv = Real(1) / v.z;  // v.z >= nearDist after clipping
    return {cx + v.x * focal_ * inv, cy - v.y * focal_ * inv, inv};
  }
  return {cx + v.x * focal_, cy - v.y * focal_, -v.z};
}

void PictureCanvas::plot(int x, int y, Real depthKey, const Rgba& color, bool writeDepth) {
  if (x < 0 || y < 0 || x >= image_.width || y >= image_.height) return;
  const std::size_t i = std::size_t(y) * std::size_t(image_.width) + std::size_t(x);
  if (depthTest_ && depthKey < depth_[i]) return;
  std::uint8_t* px = &image_.rgba[i * 4];
  if (color.a == 255) {
    px[0] = color.r;
    px[1] = color.g;
    px[2] = color.b;
  } else {
    const Real a = Real(color.a) / 255;
    px[0] = toByte(Real(px[0]) * (1 - a) + Real(color.r) * a);
    px[1] = toByte(Real(px[1]) * (1 - a) + Real(color.g) * a);
    px[2] = toByte(Real(px[2]) * (1 - a) + Real(color.b) * a);
  }
  if (writeDepth && depthTest_) depth_[i] = float(depthKey);
}

void PictureCanvas::fillTriangle(const Projected& a, const Projected& b, const Projected& c,
                                 const Rgba& color) {
  const Real area = edgeFunction(a.x, a.y, b.x, b.y, c.x, c.y);
  if (std::fabs(area) < Real(1e-6)) return;
  const int x0 = std::max(0, int(std::floor(std::min({a.x, b.x, c.x}))));
  const int x1 = std::min(image_.width - 1, int(std::ceil(std::max({a.x, b.x, c.x}))));
  const int y0 = std::max(0, int(std::floor(std::min({a.y, b.y, c.y}))));
  const int y1 = std::min(image_.height - 1, int(std::ceil(std::max({a.y, b.y, c.y}))));
  const bool writeDepth = color.a == 255;
  for (int y = y0; y <= y1; ++y) {
    const Real py = Real(y) + Real(0.5);
    for (int x = x0; x <= x1; ++x) {
      const Real px = Real(x) + Real(0.5);
      // Barycentric weights; the sign of the area makes both windings fill.
      const Real w0 = edgeFunction(b.x, b.y, c.x, c.y, px, py) / area;
      const Real w1 = edgeFunction(c.x, c.y, a.x, a.y, px, py) / area;
      const Real w2 = 1 - w0 - w1;
      if (w0 < 0 || w1 < 0 || w2 < 0) continue;
      plot(x, y, w0 * a.depthKey + w1 * b.depthKey + w2 * c.depthKey, color, writeDepth);
    }
  }
}

void PictureCanvas::polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
                            const DrawTag&) {
  if (points.size() < 3) return;
  // Shade by the normal; polygons seen from behind are dimmed.
  Real light = kAmbient + kDiffuse * std::max(Real(0), normal.dot(kLightDirection.normalized()));
  const Vec3 toEye = camera_.perspective ? camera_.eye - points[0] : -camera_.forward;
  if (normal.dot(toEye) < 0) light *= kBackFaceDim;
  const Rgba shaded = shade(color, light);

  // Clip against the near plane (Sutherland-Hodgman), then fan.
  std::vector<Vec3> view;
  view.reserve(points.size() + 2);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3 a = toView(points[i]);
    const Vec3 b = toView(points[(i + 1) % points.size()]);
    if (!camera_.perspective) {
      view.push_back(a);
      continue;
    }
    const bool aIn = a.z >= camera_.nearDist;
    const bool bIn = b.z >= camera_.nearDist;
    if (aIn) view.push_back(a);
    if (aIn != bIn) view.push_back(a + (b - a) * ((camera_.nearDist - a.z) / (b.z - a.z)));
  }
  if (view.size() < 3) return;
  const Projected p0 = project(view[0]);
  for (std::size_t i = 1; i + 1 < view.size(); ++i)
    fillTriangle(p0, project(view[i]), project(view[i + 1]), shaded);
}

void PictureCanvas::line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag&) {
  Vec3 va = toView(a);
  Vec3 vb = toView(b);
  if (camera_.perspective) {
    if (va.z < camera_.nearDist && vb.z < camera_.nearDist) return;
    if (va.z < camera_.nearDist) va = va + (vb - va) * ((camera_.nearDist - va.z) / (vb.z - va.z));
    if (vb.z < camera_.nearDist) vb = vb + (va - vb) * ((camera_.nearDist - vb.z) / (va.z - vb.z));
  }
  const Projected pa = project(va);
  const Projected pb = project(vb);
  const Real dx = pb.x - pa.x;
  const Real dy = pb.y - pa.y;
  // Skip lines whose ends are absurdly far off screen (nothing to see, and
  // the step count would explode).
  const Real limit = Real(16) * Real(std::max(image_.width, image_.height));
  if (std::fabs(pa.x) > limit || std::fabs(pa.y) > limit || std::fabs(pb.x) > limit ||
      std::fabs(pb.y) > limit)
    return;
  const int steps = std::max(1, int(std::ceil(std::max(std::fabs(dx), std::fabs(dy)))));
  for (int s = 0; s <= steps; ++s) {
    const Real t = Real(s) / Real(steps);
    const Real key = pa.depthKey + (pb.depthKey - pa.depthKey) * t;
    const Real biased = key + std::fabs(key) * kLineDepthBias;
    plot(int(std::floor(pa.x + dx * t)), int(std::floor(pa.y + dy * t)), biased, color, false);
  }
}

void PictureCanvas::text(const Vec3& at, std::string_view text, const Rgba& color, const DrawTag&) {
  const Vec3 v = toView(at);
  if (camera_.perspective && v.z < camera_.nearDist) return;
  const Projected p = project(v);
  std::string chars(text);
  std::vector<char> buffer(kTextBufferBytes);
  const int quads = stb_easy_font_print(0, 0, chars.data(), nullptr, buffer.data(), int(buffer.size()));
  const bool saved = depthTest_;
  depthTest_ = false;
  for (int q = 0; q < quads; ++q) {
    float xs[4], ys[4];
    for (int k = 0; k < 4; ++k) {
      const char* vert = buffer.data() + (std::size_t(q) * 4 + std::size_t(k)) * kTextVertexBytes;
      std::memcpy(&xs[k], vert, sizeof(float));
      std::memcpy(&ys[k], vert + sizeof(float), sizeof(float));
    }
    const auto x0 = int(std::floor(p.x + xs[0] * kTextScale));
    const auto x1 = int(std::ceil(p.x + xs[2] * kTextScale));
    const auto y0 = int(std::floor(p.y + ys[0] * kTextScale));
    const auto y1 = int(std::ceil(p.y + ys[2] * kTextScale));
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) plot(x, y, 0, color, false);
  }
  depthTest_ = saved;
}

Image renderPicture(std::span<const ModelPtr> models, std::span<const TraceRecord> traces,
                    const PictureOptions& options) {
  // The scene's bounds: every model and every trace end point.
  Bounds scene;
  auto placementOf = [&](std::size_t i) {
    return i < options.placements.size() ? options.placements[i] : Placement{};
  };
  for (std::size_t i = 0; i < models.size(); ++i) {
    if (!models[i] || models[i]->bounds().isCleared()) continue;
    const Placement place = placementOf(i);
    const Bounds& b = models[i]->bounds();
    for (int corner = 0; corner < 8; ++corner)
      scene.addPoint(Vec3{b[corner & 1].x, b[(corner >> 1) & 1].y, b[(corner >> 2) & 1].z} * place.axis +
                     place.origin);
  }
  for (const TraceRecord& r : traces) {
    if (!r.error.empty() || r.op.empty()) continue;
    scene.addPoint(r.start);
    scene.addPoint(r.end);
  }
  if (scene.isCleared()) scene = Bounds{{-64, -64, -64}, {64, 64, 64}};
  const Real aspect = Real(options.width) / Real(std::max(options.height, 1));
  const Camera camera = options.camera ? *options.camera : frameCamera(scene, options.view, aspect);

  std::optional<Real> cut = options.cutHeight;
  if (!cut && options.view == CameraView::TopDown && !options.camera)
    cut = scene.max.z - scene.size().z * kAutoCutFraction;

  PictureCanvas canvas(options.width, options.height, camera, options.background);
  // Geometry above the cut is clipped away by drawing through a filter.
  class CutFilter final : public DebugDraw {
   public:
    CutFilter(DebugDraw& out, std::optional<Real> cut) : out_(out), cut_(cut) {}
    void line(const Vec3& a, const Vec3& b, const Rgba& c, const DrawTag& t) override {
      if (!cut_) return out_.line(a, b, c, t);
      const Real h = *cut_;
      if (a.z > h && b.z > h) return;
      const auto at = [&](const Vec3& p, const Vec3& q) { return p + (q - p) * ((h - p.z) / (q.z - p.z)); };
      out_.line(a.z > h ? at(a, b) : a, b.z > h ? at(b, a) : b, c, t);
    }
    void polygon(std::span<const Vec3> pts, const Vec3& n, const Rgba& c, const DrawTag& t) override {
      if (!cut_) return out_.polygon(pts, n, c, t);
      // Keep the part below the cut (Sutherland-Hodgman against z <= cut).
      const Real h = *cut_;
      clipped_.clear();
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const Vec3& p = pts[i];
        const Vec3& q = pts[(i + 1) % pts.size()];
        if (p.z <= h) clipped_.push_back(p);
        if ((p.z <= h) != (q.z <= h)) clipped_.push_back(p + (q - p) * ((h - p.z) / (q.z - p.z)));
      }
      if (clipped_.size() >= 3) out_.polygon(clipped_, n, c, t);
    }
    void text(const Vec3& at, std::string_view s, const Rgba& c, const DrawTag& t) override {
      out_.text(at, s, c, t);
    }

   private:
    DebugDraw& out_;
    std::optional<Real> cut_;
    std::vector<Vec3> clipped_;
  };
  CutFilter filtered(canvas, cut);

  DrawOptions draw;
  draw.contentMask = options.contentMask;
  draw.filled = true;
  draw.viewOrigin = camera.eye;
  for (std::size_t i = 0; i < models.size(); ++i)
    if (models[i]) drawModel(filtered, *models[i], placementOf(i), draw);
  if (options.wireframe) {
    DrawOptions wire = draw;
    wire.filled = false;
    wire.colorByContents = false;
    wire.color = Rgba{20, 20, 24, 255};
    wire.internalEdges = options.internalEdges;
    for (std::size_t i = 0; i < models.size(); ++i)
      if (models[i]) drawModel(filtered, *models[i], placementOf(i), wire);
  }
  canvas.setDepthTest(!options.tracesOnTop);
  drawTraceRecords(canvas, traces);
  if (options.overlay) options.overlay(canvas);
  return canvas.image();
}

}  // namespace cmkit
