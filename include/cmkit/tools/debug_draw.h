// debug_draw.h: drawing collision models and traces through a tiny interface
// (the original's CollisionModel_debug.cpp, without a renderer).
//
// CONTRACT
// - The library never depends on a renderer: drawModel() and drawTrace()
//   walk the geometry and call a DebugDraw that the caller implements (a
//   recorder, the software rasteriser of picture.h, the glTF/OBJ
//   writers of export.h, an engine's debug renderer...).
// - Everything handed to a DebugDraw is in WORLD space (the model's
//   placement applied), in map units.
// - drawModel() follows the original's DrawModel: polygons whose contents
//   match the mask, optionally only those whose bounds lie within `radius`
//   of the view origin (walking only the tree nodes that can hold them),
//   optionally back-face culled against the view origin; filled polygons or
//   their edges (each edge once), internal edges only on request, edges with
//   more than two users in their own colour, edge and polygon normals as
//   short lines.
// - Every call carries a DrawTag saying what the primitive shows (polygon,
//   internal edge, contact normal...), its contents and its feature number,
//   so that a writer can group, colour or filter primitives.
// THREAD SAFETY
// - drawModel()/drawTrace() are const functions of the model; they keep no
//   state between calls. A DebugDraw is called from the calling thread only.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/trace_model.h"

namespace cmkit {

/// A colour, 8 bits per channel, non-premultiplied alpha (255 = opaque).
struct Rgba {
  /// Red, green, blue and alpha channels.
  ///@{
  std::uint8_t r = 255, g = 255, b = 255, a = 255;
  ///@}
  /// Same channels.
  constexpr bool operator==(const Rgba&) const = default;
};

/// Colours the original's debug drawing uses.
namespace colors {
/// Red.
inline constexpr Rgba kRed{255, 0, 0, 255};
/// Green.
inline constexpr Rgba kGreen{0, 255, 0, 255};
/// Blue.
inline constexpr Rgba kBlue{0, 0, 255, 255};
/// Cyan.
inline constexpr Rgba kCyan{0, 255, 255, 255};
/// Magenta.
inline constexpr Rgba kMagenta{255, 0, 255, 255};
/// Yellow.
inline constexpr Rgba kYellow{255, 255, 0, 255};
/// White.
inline constexpr Rgba kWhite{255, 255, 255, 255};
/// Orange.
inline constexpr Rgba kOrange{255, 128, 0, 255};
}  // namespace colors

/// What a drawn primitive shows.
enum class DrawKind : std::uint8_t {
  Polygon,        ///< a model polygon (filled)
  Edge,           ///< a model edge used by one or two polygons
  SharedEdge,     ///< a model edge used by more than two polygons
  InternalEdge,   ///< an internal model edge (never hit by traces)
  EdgeNormal,     ///< a model edge's normal
  PolygonNormal,  ///< a model polygon's normal
  TracePath,      ///< the line from a trace's start to where it stopped (and on to its end)
  TraceModel,     ///< the trace model at the start or end pose
  Contact,        ///< the marker at a contact point
  ContactNormal,  ///< the contact normal
  Label,          ///< text
};

/// Name of a kind ("polygon", "internal edge", ...).
std::string_view toString(DrawKind kind);

/// Which part of a model or trace a primitive belongs to.
struct DrawTag {
  /// What the primitive shows.
  DrawKind kind = DrawKind::Polygon;
  /// Contents of the polygon or edge's polygon (model primitives), of the
  /// surface hit (contact primitives), else 0.
  std::uint32_t contents = 0;
  /// Polygon index (Polygon, PolygonNormal), edge number (edges), trace
  /// index (trace primitives), else -1.
  std::int32_t feature = -1;
};

/// The drawing interface. Implement it to see models and traces anywhere.
class DebugDraw {
 public:
  virtual ~DebugDraw() = default;
  /// A line segment from a to b.
  virtual void line(const Vec3& a, const Vec3& b, const Rgba& color, const DrawTag& tag) = 0;
  /// A filled convex polygon, points in order (counter-clockwise seen from
  /// the front, the side `normal` points to).
  virtual void polygon(std::span<const Vec3> points, const Vec3& normal, const Rgba& color,
                       const DrawTag& tag) = 0;
  /// A text label anchored at a point.
  virtual void text(const Vec3& at, std::string_view text, const Rgba& color, const DrawTag& tag) = 0;
};

/// Length of drawn normals (map units), as in the original.
inline constexpr Real kDrawNormalLength = 5;

/// Options of drawModel (the original's cm_draw* cvars).
struct DrawOptions {
  /// Only polygons with one of these content flags are drawn (cm_drawMask).
  std::uint32_t contentMask = contents::kMaskAll;
  /// Colour each polygon by its contents (contentColor), else use `color`.
  bool colorByContents = true;
  /// The colour when not colouring by contents (cm_drawColor).
  Rgba color = colors::kRed;
  /// Filled polygons, else their edges (cm_drawFilled).
  bool filled = false;
  /// Draw internal edges, in green (cm_drawInternal).
  bool internalEdges = false;
  /// Draw edge normals (cyan) and polygon normals (magenta) (cm_drawNormals).
  bool normals = false;
  /// Skip polygons whose front the view origin cannot see (cm_backFaceCull).
  bool backFaceCull = false;
  /// The viewer's position in world space (culling and radius).
  Vec3 viewOrigin;
  /// When > 0, only polygons whose bounds come within this distance of the
  /// view origin on every axis.
  Real radius = 0;
};

/// Draws a placed collision model.
void drawModel(DebugDraw& draw, const CollisionModel& model, const Placement& placement,
               const DrawOptions& options);

/// Draws the edges of a trace model placed at `origin` with orientation
/// `axis` (a point: a small cross).
void drawTraceModel(DebugDraw& draw, const TraceModel* trm, const Vec3& origin, const Mat3& axis,
                    const Rgba& color, const DrawTag& tag);

/// One trace to draw: a query and its result.
struct TraceDrawing {
  const TraceModel* trm = nullptr;  ///< nullptr or a point shape: a point trace
  /// Orientation of the trace model at the start.
  Mat3 trmAxis;
  /// Start of the trace.
  Vec3 start;
  /// End the trace aimed for.
  Vec3 end;
  /// The query's result.
  TraceResult result;
  std::int32_t index = 0;  ///< goes to DrawTag::feature
};

/// Draws a trace: the path start -> stop point (yellow) and on to the end
/// (dimmed), the trace model at the start (dim) and at the end pose (white),
/// the contact point (a red marker) and normal (orange) when it hit.
void drawTrace(DebugDraw& draw, const TraceDrawing& trace);

/// Colour for content flags: the colour of the lowest named flag set
/// (solid grey, water blue, playerclip magenta, ...); grey-pink for none.
Rgba contentColor(std::uint32_t contents);

/// One row of the content name/colour table.
struct ContentStyle {
  /// Name of the content flag.
  std::string_view name;
  /// The flag's bit.
  std::uint32_t flag;
  /// The colour drawn for it.
  Rgba color;
};

/// The content name/colour table, in bit order (the original's
/// cm_contentsNameByIndex / cm_contentsFlagByIndex plus a colour).
std::span<const ContentStyle> contentStyles();

// ---- traces read from query and result files --------------------------------

/// A query line and its result line, parsed for drawing.
struct TraceRecord {
  /// The query line as read.
  std::string queryLine;
  /// Its result line as read.
  std::string resultLine;
  std::string op;  ///< "translation", "rotation", "contents", ...
  /// The trace model (empty: a point).
  std::optional<TraceModel> trm;
  /// Orientation of the trace model at the start.
  Mat3 trmAxis;
  /// Start position.
  Vec3 start;
  Vec3 end;  ///< = start for queries that do not move
  /// The result (fraction, end pose, contact); fraction 1 and no contact
  /// when the result line is an error or has no trace fields.
  TraceResult result;
  std::string error;  ///< the result's error=..., or why the lines could not be read
  /// The entity hit (entity=, or entity.0= of a contacts line: world
  /// queries, cmkit query --world); empty when none.
  std::string entity;
};

/// Pairs query lines with result lines. With `queriesText` empty,
/// `resultsText` holds both, each query line followed by its result line.
/// Lines that are blank or comments are skipped. Lines that cannot be
/// parsed give records with `error` set, never an exception.
std::vector<TraceRecord> parseTraceRecords(std::string_view queriesText, std::string_view resultsText);

/// Draws every record that has a start (translations, rotations, contents
/// and contacts queries) with drawTrace.
void drawTraceRecords(DebugDraw& draw, std::span<const TraceRecord> records);

}  // namespace cmkit
