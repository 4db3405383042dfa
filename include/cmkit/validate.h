// validate.h: checking the invariants of a collision model (for `cmkit
// validate`, tests, and anyone loading models from untrusted files).
//
// Checks, each violation reported with the model name and item number:
//  - vertices: finite coordinates;
//  - edges: vertex numbers in range, two different vertices, used by at most
//    two polygons (and by two only in opposite directions);
//  - polygons: at least 3 edges, edge numbers in range and not 0, no edge
//    twice, the edge loop continuous (each edge starts where the previous
//    one ends), a unit normal, every vertex within tol::kValidatePlanarEpsilon
//    of the plane, the bounds containing the vertices (within
//    tol::kValidateBoundsEpsilon), a material index in range;
//  - brushes: unit normals, the planes enclosing a bounded, non-empty
//    volume whose corners lie inside the brush bounds (within
//    tol::kValidateBoundsEpsilon), plane ranges in range;
//  - tree: nodes[0] the root, children and parents consistent, pre-order
//    storage, plane types 0..2, reference ranges and item numbers in range,
//    every polygon and brush referenced at least once, every referenced
//    item's bounds touching its node's region, the model bounds containing
//    every item.
// Each violation says whether it is one of structure (corrupt data) or of
// geometry (an odd shape; see Violation::Kind).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cmkit/model.h"

namespace cmkit {

/// One broken invariant.
struct Violation {
  /// Structure: a number, range, link or loop is wrong (indices out of
  /// range, a broken edge loop, a tree that is not a tree): the model is
  /// corrupt and queries may read the wrong data. Geometry: the numbers
  /// describe an odd shape that queries handle (a degenerate or non-planar
  /// polygon, an empty brush, an edge shared by three polygons, non-finite
  /// coordinates); real maps give some, and the map compiler keeps them as
  /// the original does.
  enum class Kind { Structure, Geometry };

  std::string model;     ///< model name
  std::string itemKind;  ///< "vertex", "edge", "polygon", "brush", "node" or "model"
  /// Index of the item (-1 for the model itself).
  std::int64_t item = -1;
  /// What is wrong.
  std::string message;
  /// Structure (the model is unusable) or geometry.
  Kind kind = Kind::Structure;

  /// "model "NAME" polygon 12: message".
  std::string toString() const;
};

/// Every violation of the model's invariants (empty: all hold). At most
/// `maxViolations` are reported.
std::vector<Violation> validateModel(const CollisionModel& model, std::size_t maxViolations = 1000);
/// The same for arrays not (yet) sealed into a model: what
/// CollisionModel::create checks (it refuses arrays with a violation of
/// structure), and a way to see every violation of hand-made arrays.
std::vector<Violation> validateModel(const ModelArrays& arrays, std::size_t maxViolations = 1000);
/// Only the violations of structure (Violation::Kind::Structure) of `arrays`,
/// at most `maxViolations`: empty when CollisionModel::create accepts them.
std::vector<Violation> structureViolations(const ModelArrays& arrays, std::size_t maxViolations = 1000);

}  // namespace cmkit
