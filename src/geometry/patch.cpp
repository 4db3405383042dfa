// Patch tessellation for collision, from cm-algorithms.md section 3 step 6.
//
// The grid is kept as rows (rows[i][j]: row i = second index, column j =
// first index, as in MapPatch). Every float expression is evaluated in the
// original's order so that the grid points match it bit for bit.
#include "geometry/patch.h"

#include <cstddef>

#include "cmkit/tolerances.h"

namespace cmkit {

namespace {

using Rows = std::vector<std::vector<Vec3>>;

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

int width(const Rows& rows) { return rows.empty() ? 0 : static_cast<int>(rows[0].size()); }
int height(const Rows& rows) { return static_cast<int>(rows.size()); }

/// Splits every 3-point span along the width (columns j, j+1, j+2) whose
/// middle point is off the curve in any row, re-checking the same span after
/// each split (de Casteljau: a, mid(a,b), curve point, mid(b,c), c).
void subdivideWidth(Rows& rows, Real maxErrorSquared) {
  for (int j = 0; j + 2 < width(rows); j += 2) {
    bool split = false;
    for (const auto& row : rows) {
      const auto k = static_cast<std::size_t>(j);
      if (spanNeedsSplit(row[k], row[k + 1], row[k + 2], maxErrorSquared)) {
        split = true;
        break;
      }
    }
    if (!split) continue;
    if (static_cast<long long>(width(rows) + 2) * height(rows) > tol::kMaxPatchGridPoints) continue;
    for (auto& row : rows) {
      const auto k = static_cast<std::size_t>(j);
      const Vec3 prev = lerpHalf(row[k], row[k + 1]);
      const Vec3 next = lerpHalf(row[k + 1], row[k + 2]);
      const Vec3 mid = lerpHalf(prev, next);
      row[k + 1] = prev;
      row.insert(row.begin() + static_cast<std::ptrdiff_t>(k) + 2, {mid, next});
    }
    j -= 2;  // check the first half again
  }
}

/// As subdivideWidth, along the height (rows i, i+1, i+2).
void subdivideHeight(Rows& rows, Real maxErrorSquared) {
  for (int i = 0; i + 2 < height(rows); i += 2) {
    const auto k = static_cast<std::size_t>(i);
    bool split = false;
    for (int j = 0; j < width(rows); ++j) {
      const auto c = static_cast<std::size_t>(j);
      if (spanNeedsSplit(rows[k][c], rows[k + 1][c], rows[k + 2][c], maxErrorSquared)) {
        split = true;
        break;
      }
    }
    if (!split) continue;
    if (static_cast<long long>(height(rows) + 2) * width(rows) > tol::kMaxPatchGridPoints) continue;
    std::vector<Vec3> prevRow(rows[k].size());
    std::vector<Vec3> midRow(rows[k].size());
    std::vector<Vec3> nextRow(rows[k].size());
    for (std::size_t c = 0; c < rows[k].size(); ++c) {
      prevRow[c] = lerpHalf(rows[k][c], rows[k + 1][c]);
      nextRow[c] = lerpHalf(rows[k + 1][c], rows[k + 2][c]);
      midRow[c] = lerpHalf(prevRow[c], nextRow[c]);
    }
    rows[k + 1] = std::move(prevRow);
    rows.insert(rows.begin() + static_cast<std::ptrdiff_t>(k) + 2, {std::move(midRow), std::move(nextRow)});
    i -= 2;
  }
}

/// The point on the curve for the off-curve control point `it` between
/// `before` and `after`: the midpoint of the two half-way points.
Vec3 onCurve(const Vec3& before, const Vec3& it, const Vec3& after) {
  const Vec3 towardAfter = lerpHalf(it, after);
  const Vec3 towardBefore = lerpHalf(it, before);
  return lerpHalf(towardAfter, towardBefore);
}

/// Moves every odd-indexed point onto the curve: odd rows first (along the
/// height), then odd columns (along the width, using the moved rows).
void putOnCurve(Rows& rows) {
  const int w = width(rows);
  const int h = height(rows);
  for (int j = 0; j < w; ++j) {
    const auto c = static_cast<std::size_t>(j);
    for (int i = 1; i + 1 < h; i += 2) {
      const auto r = static_cast<std::size_t>(i);
      rows[r][c] = onCurve(rows[r - 1][c], rows[r][c], rows[r + 1][c]);
    }
  }
  for (auto& row : rows) {
    for (int j = 1; j + 1 < w; j += 2) {
      const auto c = static_cast<std::size_t>(j);
      row[c] = onCurve(row[c - 1], row[c], row[c + 1]);
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

/// Removes interior columns, then rows, whose points all lie within
/// tol::kPatchStraightEpsilon of the line through their two neighbours.
void removeStraightColumnsAndRows(Rows& rows) {
  const Real limit = tol::kPatchStraightEpsilon * tol::kPatchStraightEpsilon;
  for (int j = 1; j + 1 < width(rows); ++j) {
    const auto c = static_cast<std::size_t>(j);
    Real worst = 0;
    for (const auto& row : rows) {
      const Real d = distanceFromLineSquared(row[c], row[c - 1], row[c + 1]);
      if (d > worst) worst = d;
    }
    if (worst < limit) {
      for (auto& row : rows) row.erase(row.begin() + j);
      --j;
    }
  }
  for (int i = 1; i + 1 < height(rows); ++i) {
    const auto r = static_cast<std::size_t>(i);
    Real worst = 0;
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      const Real d = distanceFromLineSquared(rows[r][c], rows[r - 1][c], rows[r + 1][c]);
      if (d > worst) worst = d;
    }
    if (worst < limit) {
      rows.erase(rows.begin() + i);
      --i;
    }
  }
}

/// One quadratic Bézier coordinate, in the original's float order:
/// (a - 2b + c) u u + (2b - 2a) u + a.
Real quadratic(Real a, Real b, Real c, Real u) {
  const Real qa = a - 2.0f * b + c;
  const Real qb = 2.0f * b - 2.0f * a;
  return qa * u * u + qb * u + a;
}

Rows toRows(const MapPatch& patch) {
  Rows rows(static_cast<std::size_t>(patch.height));
  for (int i = 0; i < patch.height; ++i) {
    auto& row = rows[static_cast<std::size_t>(i)];
    const auto begin = patch.points.begin() + static_cast<std::ptrdiff_t>(i) * patch.width;
    row.assign(begin, begin + patch.width);
  }
  return rows;
}

/// patchDef3: every 3x3 block sampled at (horz+1) x (vert+1) parameter
/// values; blocks share their border points, the later block's value wins.
Rows subdivideExplicit(const MapPatch& patch) {
  const int horz = patch.horzSubdivisions;
  const int vert = patch.vertSubdivisions;
  const int outWidth = (patch.width - 1) / 2 * horz + 1;
  const int outHeight = (patch.height - 1) / 2 * vert + 1;
  Rows rows(static_cast<std::size_t>(outHeight), std::vector<Vec3>(static_cast<std::size_t>(outWidth)));
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
  Rows rows;
  if (patch.explicitSubdivisions && patch.horzSubdivisions > 0 && patch.vertSubdivisions > 0) {
    const long long outWidth = static_cast<long long>((patch.width - 1) / 2) * patch.horzSubdivisions + 1;
    const long long outHeight = static_cast<long long>((patch.height - 1) / 2) * patch.vertSubdivisions + 1;
    if (outWidth * outHeight > tol::kMaxPatchGridPoints) return grid;
    rows = subdivideExplicit(patch);
  } else {
    rows = toRows(patch);
    const Real maxErrorSquared = tol::kCurveMaxErrorCollision * tol::kCurveMaxErrorCollision;
    subdivideWidth(rows, maxErrorSquared);
    subdivideHeight(rows, maxErrorSquared);
    putOnCurve(rows);
  }
  removeStraightColumnsAndRows(rows);
  grid.width = width(rows);
  grid.height = height(rows);
  grid.points.reserve(static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height));
  for (const auto& row : rows) grid.points.insert(grid.points.end(), row.begin(), row.end());
  return grid;
}

}  // namespace cmkit
