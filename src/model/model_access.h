// Internal: how the library makes sealed models (CollisionModel's friend).
// The compiler, the .cm reader and the conversions fill a ModelArrays and
// seal it here; outside code goes through CollisionModel::create, which
// checks the arrays' structure first.
#pragma once

#include <utility>

#include "cmkit/model.h"

namespace cmkit::detail {

struct QueryData;

struct ModelAccess {
  /// Seals arrays the library made itself (their structure is right by
  /// construction: CMKIT_ASSERT checks it in builds with asserts).
  static ModelPtr seal(ModelArrays arrays);
  /// The model's query data (never null for a model made by seal or create;
  /// null only for withoutQueryData's copies).
  static const QueryData* queryData(const CollisionModel& m) { return m.queryData_.get(); }
  /// A copy of `m` without its query data, for tests that compare the
  /// queries' paths with and without it (the results must be the same).
  static CollisionModel withoutQueryData(const CollisionModel& m) {
    CollisionModel copy = m;
    copy.queryData_.reset();
    return copy;
  }
};

}  // namespace cmkit::detail
