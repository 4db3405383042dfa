// Patch tessellation for collision, as the original does it (docs/algorithms.md, "Building a model").
//
// The grid is kept as lines of points, rows (rows[i][j]: row i = second
// index, column j = first index, as in MapPatch) or columns, transposed
// between the passes so that every pass is linear in the grid size. Every float expression is evaluated in
// the original's order so that the grid points match it bit for bit.
#include "geometry/patch.h"

#include <cstddef>

#include "cmkit/tolerances.h"

namespace cmkit::detail {

namespace {

/// A grid as lines of points: either its rows or its columns.
using Lines = std::vector<std::vector<Vec3>>;

/// The midpoint 0.5 * (a + b), per component.
Vec3 lerpHalf(const Vec3& a, const Vec3& b) {
  return {0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z)};
}

/// True when the middle control point b of the span a-b-c is farther than
/// the allowed error from the curve point (a + 2b + c) / 4.
bool spanNeedsSplit(const Vec3& a, const Vec3& b, const Vec3& c, Real maxErrorSquared) {
  const Vec3 mid{(a.x + b.x * 2.0f + c.x) * 0.25f, (a.y + b.y * 2.0f + c.y) * 0.25f,
                 (a.z + b.z * 2.0f + c.z) * 0.25f};
  return (b - mid).lengthSquared() > maxErrorSquared;
}

/// The grid transposed: rows <-> columns.
Lines transpose(const Lines& lines) {
  if (lines.empty()) return {};
  Lines out(lines[0].size(), std::vector<Vec3>(lines.size()));
  for (std::size_t a = 0; a < lines.size(); ++a) {
    for (std::size_t b = 0; b < lines[a].size(); ++b) out[b][a] = lines[a][b];
  }
  return out;
}

/// Splits every 3-line span (lines k, k+1, k+2) whose middle line is off the
/// curve at any point, re-checking the first half after each split, then
/// the second (de Casteljau: a, mid(a,b), curve point, mid(b,c), c). An
/// explicit stack replaces the original's "back up and re-check" index
/// arithmetic: same decisions in the same order, in linear time.
void subdivideLines(Lines& lines, Real maxErrorSquared) {
  if (lines.size() < 3) return;
  const std::size_t n = lines[0].size();
  std::size_t count = lines.size();  // the line count the original would have now
  Lines out;
  out.push_back(lines[0]);
  struct Span {
    std::vector<Vec3> a, b, c;
  };
  std::vector<Span> pending;
  for (std::size_t k = 0; k + 2 < lines.size(); k += 2) {
    pending.push_back({lines[k], lines[k + 1], lines[k + 2]});
    while (!pending.empty()) {
      Span span = std::move(pending.back());
      pending.pop_back();
      bool split = false;
      for (std::size_t i = 0; i < n && !split; ++i) {
        split = spanNeedsSplit(span.a[i], span.b[i], span.c[i], maxErrorSquared);
      }
      if (split &&
          static_cast<long long>(count + 2) * static_cast<long long>(n) <= tol::kMaxPatchGridPoints) {
        count += 2;
        Span left{std::move(span.a), std::vector<Vec3>(n), std::vector<Vec3>(n)};
        Span right{std::vector<Vec3>(n), std::vector<Vec3>(n), std::move(span.c)};
        for (std::size_t i = 0; i < n; ++i) {
          left.b[i] = lerpHalf(left.a[i], span.b[i]);    // prev
          right.b[i] = lerpHalf(span.b[i], right.c[i]);  // next
          left.c[i] = lerpHalf(left.b[i], right.b[i]);   // on the curve
          right.a[i] = left.c[i];
        }
        pending.push_back(std::move(right));
        pending.push_back(std::move(left));
      } else {
        out.push_back(std::move(span.b));
        out.push_back(std::move(span.c));
      }
    }
  }
  lines = std::move(out);
}

/// The point on the curve for the off-curve control point `it` between
/// `before` and `after`: the midpoint of the two half-way points (the
/// original's order of operations, not (before + 2 it + after) / 4).
Vec3 onCurve(const Vec3& before, const Vec3& it, const Vec3& after) {
  const Vec3 towardAfter = lerpHalf(it, after);
  const Vec3 towardBefore = lerpHalf(it, before);
  return lerpHalf(towardAfter, towardBefore);
}

/// Moves every point of every odd line onto the curve across the lines.
void putOnCurve(Lines& lines) {
  for (std::size_t k = 1; k + 1 < lines.size(); k += 2) {
    for (std::size_t i = 0; i < lines[k].size(); ++i) {
      lines[k][i] = onCurve(lines[k - 1][i], lines[k][i], lines[k + 1][i]);
    }
  }
}

/// Squared distance of p from the line through a and b (the projection uses
/// the normalised direction; a zero direction projects onto a).
Real distanceFromLineSquared(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 fromA = p - a;
  Vec3 dir = b - a;
  dir.normalize();
  const Real along = fromA.dot(dir);
  const Vec3 projected = a + dir * along;
  return (p - projected).lengthSquared();
}

/// Removes every interior line whose points all lie within
/// tol::kPatchStraightEpsilon of the line through the same points of its
/// neighbours. As in the original, a removed line is gone when its successor
/// is checked (its left neighbour is the last line kept).
void removeStraightLines(Lines& lines) {
  if (lines.size() < 3) return;
  const Real limit = tol::kPatchStraightEpsilon * tol::kPatchStraightEpsilon;
  std::vector<std::size_t> kept{0};
  for (std::size_t k = 1; k + 1 < lines.size(); ++k) {
    const auto& left = lines[kept.back()];
    const auto& right = lines[k + 1];
    Real worst = 0;
    for (std::size_t i = 0; i < lines[k].size(); ++i) {
      const Real d = distanceFromLineSquared(lines[k][i], left[i], right[i]);
      if (d > worst) worst = d;
    }
    if (!(worst < limit)) kept.push_back(k);
  }
  kept.push_back(lines.size() - 1);
  Lines out;
  out.reserve(kept.size());
  for (std::size_t k : kept) out.push_back(std::move(lines[k]));
  lines = std::move(out);
}

/// One quadratic Bézier coordinate, in the original's float order:
/// (a - 2b + c) u u + (2b - 2a) u + a.
Real quadratic(Real a, Real b, Real c, Real u) {
  const Real qa = a - 2.0f * b + c;
  const Real qb = 2.0f * b - 2.0f * a;
  return qa * u * u + qb * u + a;
}

Lines toRows(const MapPatch& patch) {
  Lines rows(static_cast<std::size_t>(patch.height));
  for (int i = 0; i < patch.height; ++i) {
    auto& row = rows[static_cast<std::size_t>(i)];
    const auto begin = patch.points.begin() + static_cast<std::ptrdiff_t>(i) * patch.width;
    row.assign(begin, begin + patch.width);
  }
  return rows;
}

/// patchDef3: every 3x3 block sampled at (horz+1) x (vert+1) parameter
/// values; blocks share their border points, the later block's value wins.
Lines subdivideExplicit(const MapPatch& patch) {
  const int horz = patch.horzSubdivisions;
  const int vert = patch.vertSubdivisions;
  const int outWidth = (patch.width - 1) / 2 * horz + 1;
  const int outHeight = (patch.height - 1) / 2 * vert + 1;
  Lines rows(static_cast<std::size_t>(outHeight), std::vector<Vec3>(static_cast<std::size_t>(outWidth)));
  auto at = [&](int column, int row) {
    return patch.points[static_cast<std::size_t>(row) * static_cast<std::size_t>(patch.width) +
                        static_cast<std::size_t>(column)];
  };
  int baseColumn = 0;
  for (int bj = 0; bj + 2 < patch.width; bj += 2) {
    int baseRow = 0;
    for (int bi = 0; bi + 2 < patch.height; bi += 2) {
      Vec3 ctrl[3][3];  // [column offset][row offset]
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < 3; ++l) ctrl[k][l] = at(bj + k, bi + l);
      }
      for (int s = 0; s <= horz; ++s) {
        for (int t = 0; t <= vert; ++t) {
          const Real u = static_cast<Real>(s) / static_cast<Real>(horz);
          const Real v = static_cast<Real>(t) / static_cast<Real>(vert);
          rows[static_cast<std::size_t>(baseRow + t)][static_cast<std::size_t>(baseColumn + s)] =
              sampleBezierPatchPoint(ctrl, u, v);
        }
      }
      baseRow += vert;
    }
    baseColumn += horz;
  }
  return rows;
}

}  // namespace

Vec3 sampleBezierPatchPoint(const Vec3 (&ctrl)[3][3], Real u, Real v) {
  Vec3 alongU[3];
  for (int l = 0; l < 3; ++l) {
    for (int axis = 0; axis < 3; ++axis) {
      alongU[l][axis] = quadratic(ctrl[0][l][axis], ctrl[1][l][axis], ctrl[2][l][axis], u);
    }
  }
  Vec3 out;
  for (int axis = 0; axis < 3; ++axis)
    out[axis] = quadratic(alongU[0][axis], alongU[1][axis], alongU[2][axis], v);
  return out;
}

PatchGrid subdividePatchForCollision(const MapPatch& patch) {
  PatchGrid grid;
  if (patch.width < 3 || patch.height < 3 || patch.width % 2 == 0 || patch.height % 2 == 0 ||
      patch.points.size() != static_cast<std::size_t>(patch.width) * static_cast<std::size_t>(patch.height)) {
    return grid;  // the parser never produces these; an empty grid is safe
  }
  Lines rows;
  if (patch.explicitSubdivisions && patch.horzSubdivisions > 0 && patch.vertSubdivisions > 0) {
    const long long outWidth = static_cast<long long>((patch.width - 1) / 2) * patch.horzSubdivisions + 1;
    const long long outHeight = static_cast<long long>((patch.height - 1) / 2) * patch.vertSubdivisions + 1;
    if (outWidth * outHeight > tol::kMaxPatchGridPoints) return grid;
    rows = subdivideExplicit(patch);
  } else {
    const Real maxErrorSquared = tol::kCurveMaxErrorCollision * tol::kCurveMaxErrorCollision;
    Lines columns = transpose(toRows(patch));
    subdivideLines(columns, maxErrorSquared);  // along the width first
    rows = transpose(columns);
    subdivideLines(rows, maxErrorSquared);  // then along the height
    putOnCurve(rows);                       // odd rows first
    columns = transpose(rows);
    putOnCurve(columns);  // then odd columns
    rows = transpose(columns);
  }
  Lines columns = transpose(rows);
  removeStraightLines(columns);  // columns first
  rows = transpose(columns);
  removeStraightLines(rows);  // then rows
  grid.height = static_cast<int>(rows.size());
  grid.width = rows.empty() ? 0 : static_cast<int>(rows[0].size());
  grid.points.reserve(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height));
  for (const auto& row : rows) grid.points.insert(grid.points.end(), row.begin(), row.end());
  return grid;
}

}  // namespace cmkit::detail
