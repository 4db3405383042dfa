// Internal: the rotation test of a trace-model edge against a model edge
// (the original's RotateTrmEdgeThroughEdge): its root search here, the rest
// in rotate_edges.cpp; called by the polygon tests of rotate.cpp for each
// pair past the culls. Solved exactly in the tangent of half the angle
// (rotate_work.h); model frame.
#pragma once

#include <cstdint>
#include <limits>

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
  VectorPair pw;  ///< (P, w), for pairDotDifference with EdgeTurn's pairs
  ModelEdgeLine(const RotationWork& rw, const Vec3& c, const Vec3& d) {
    const DVec w = DVec(d) - DVec(c);
    pw.set(w.cross(DVec(c) - DVec(rw.origin)), w);
  }
  /// The product at the start of the part (t = 0).
  double atStart(const EdgeTurn& t) const { return pairDotDifference(pw, t.start); }
  Sinusoid sinusoid(const EdgeTurn& t, double sign) const {
    Sinusoid s;
    s.v0 = pairDotDifference(pw, t.axial);
    s.v2 = pairDotDifference(pw, t.across);
    s.v1 = sign * pairDotDifference(pw, t.turned);
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

/// The rest of rotateTrmEdgeThroughEdge once the lines' product has a root
/// u below rw.maxTan (rotate_edges.cpp): whether the edges meet within both
/// segments there (else at `later`, the product's next root, when that is
/// below rw.maxTan), the contact plane, and the contact recorded (lowering
/// rw.maxTan). `inBand`: the pair started within the band, so the roots are
/// those of the band's far side (the model edge moved out by the clip plus
/// the range epsilon), else of the edge moved out by the clip epsilon.
void edgePairContact(TraceWork& tw, RotationWork& rw, const CmPolygon& poly, std::int32_t edgeNum,
                     int trmEdgeNum, double u, double later, bool inBand);

/// The first contact of trace-model edge `trmEdgeNum` with model edge
/// `edgeNum` (of `poly`, its lines in `lines`) before rw.maxTan: lowers
/// rw.maxTan and records the contact (setRotationContact) when there is one.
/// The root search is inline (always: GCC left it out of line): it runs for
/// every pair past the box culls, and about three pairs in four end there,
/// before edgePairContact. Called, it cost about 30 instructions a pair in
/// saved registers and arguments (lt4's 410 reference rotations, three
/// passes: 28 269 pairs, 0.9 M of 41.8 M instructions).
[[gnu::always_inline]] inline void rotateTrmEdgeThroughEdge(TraceWork& tw, RotationWork& rw,
                                                            const CmPolygon& poly, std::int32_t edgeNum,
                                                            const ModelEdgeLines& lines, int trmEdgeNum) {
  count(tw.scratch, &QueryStats::edgePairs);
  const EdgeTurn& turn = rw.edgeTurn(tw, trmEdgeNum);
  const double sign = rw.sign;

  // Is the trace-model edge line already between the model edge and the
  // edge moved out by the epsilon (plus the range epsilon)?
  const double f1 = lines.line.atStart(turn);
  const double f2 = lines.lineIn.atStart(turn);
  double u;
  // The next root of the product whose root u is (below); none when u = 0
  // in the band.
  double later = std::numeric_limits<double>::quiet_NaN();
  // (& and |, one branch on the answer: the signs are the data's.)
  const bool inBand = (unsigned(f1 < 0) & unsigned(f2 > 0)) | (unsigned(f1 > 0) & unsigned(f2 < 0));
  if (inBand) {
    // Within the band (on the model edge line included): the side of the
    // epsilon line is the outside, so moving away from it is moving in.
    // away = d|f1|/dt, with sign(f1) = -sign(f2) in the band.
    const Sinusoid real = lines.line.sinusoid(turn, sign);
    const double flip = f2 > 0 ? -1.0 : 1.0;
    const double away = flip * real.v1;
    if (away <= 0) {
      u = 0;
    } else {
      const double furthest = firstExtremumTan(away, flip * real.v2);
      if (!(furthest < rw.maxTan)) return;
      if (!sinusoidRoot(lines.lineIn.sinusoid(turn, sign), furthest, rw.maxTan, u, &later)) return;
    }
  } else {
    if (!sinusoidRoot(lines.lineEps.sinusoid(turn, sign), 0, rw.maxTan, u, &later)) return;
  }
  if (!(u < rw.maxTan)) return;
  edgePairContact(tw, rw, poly, edgeNum, trmEdgeNum, u, later, inBand);
}

}  // namespace cmkit::detail
