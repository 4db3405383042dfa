// Internal parts of the speed test (include/cmkit/speed_test.h): the plan of
// queries generated from the options before anything is timed.
#pragma once

#include <vector>

#include "cmkit/tools/speed_test.h"

namespace cmkit::detail {

/// One rotation of the plan, relative to the start of the move.
struct SpeedTestTurn {
  Vec3 originOffset;  ///< rotation origin = start + originOffset
  Vec3 axis;          ///< unit axis
};

/// Every query of a speed test, relative to the start of each move.
struct SpeedTestPlan {
  std::vector<Vec3> moves;           ///< end = start + moves[i]
  std::vector<SpeedTestTurn> turns;  ///< rotation i about start + originOffset
};

/// Generates the plan from the options' seed (pure function).
SpeedTestPlan planSpeedTest(const SpeedTestOptions& options);

}  // namespace cmkit::detail
