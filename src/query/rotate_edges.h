// Internal: the rotation test of a trace-model edge against a model edge
// (the original's RotateTrmEdgeThroughEdge), rotate_edges.cpp; called by the
// polygon tests of rotate.cpp for each pair past the culls. Solved exactly in
// the tangent of half the angle (rotate_work.h); model frame.
#pragma once

#include <cstdint>

#include "query/rotate_work.h"

namespace cmkit::detail {

/// The line product of the turning trace-model edge and the fixed model
/// edge line c -> d, ((e - s) x (d - c)) . (c - s) with s, e the turned
/// edge's ends (zero when the lines meet, its sign telling which way one
/// passes the other: the Pluecker permuted product), as a sinusoid of the
/// angle. With u = e - s, q = (s - o) x u (o on the axis), w = d - c and
/// P = w x (c - o) it is P . R(t) u - w . R(t) q (turning both lines keeps
/// their products), and R(t) x is linear in cos t and sin t (EdgeTurn).
/// The model edge's ends are Real: an edge moved out by an epsilon is
/// rounded as the original rounds it (a tiny turn's fraction shows it).
struct ModelEdgeLine {
  DVec w, p;
  ModelEdgeLine(const RotationWork& rw, const Vec3& c, const Vec3& d)
      : w(DVec(d) - DVec(c)), p(w.cross(DVec(c) - DVec(rw.origin))) {}
  /// The product at the start of the part (t = 0).
  double atStart(const EdgeTurn& t) const { return p.dot(t.u) - w.dot(t.q); }
  Sinusoid sinusoid(const EdgeTurn& t, double sign) const {
    Sinusoid s;
    s.v0 = p.dot(t.uAxial) - w.dot(t.qAxial);
    s.v2 = p.dot(t.uAcross) - w.dot(t.qAcross);
    s.v1 = sign * (p.dot(t.uTurned) - w.dot(t.qTurned));
    return s;
  }
};

/// The lines of a model edge c0 -> d0 that its edge pairs test against (the
/// same for every trace-model edge, so made once per model edge): the edge;
/// the edge moved out along its normal by the clip plus the range epsilon
/// (cIn -> dIn: the far side of the band); and moved out by the clip epsilon
/// alone.
struct ModelEdgeLines {
  ModelEdgeLines(const RotationWork& rw, const CmEdge& edge, const Vec3& c0, const Vec3& d0, const Vec3& cIn,
                 const Vec3& dIn)
      : line(rw, c0, d0),
        lineIn(rw, cIn, dIn),
        lineEps(rw, c0 + edge.normal * tol::kClipEpsilon, d0 + edge.normal * tol::kClipEpsilon) {}
  ModelEdgeLine line, lineIn, lineEps;
};

/// The first contact of trace-model edge `trmEdgeNum` with model edge
/// `edgeNum` (of `poly`, its lines in `lines`) before rw.maxTan: lowers
/// rw.maxTan and records the contact (setRotationContact) when there is one.
void rotateTrmEdgeThroughEdge(TraceWork& tw, RotationWork& rw, const CmPolygon& poly, std::int32_t edgeNum,
                              const ModelEdgeLines& lines, int trmEdgeNum);

}  // namespace cmkit::detail
