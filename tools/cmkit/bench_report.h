// The speed test as the CLI runs and prints it (`cmkit bench`, `cmkit demo`).
#pragma once

#include <string>

#include "cmkit/model.h"
#include "cmkit/tools/speed_test.h"

namespace cmkit::cli {

/// The default trace model of the speed test (the original's cm_testBox).
inline constexpr const char* kSpeedTestDefaultTrm = "box:-16,-16,0,16,16,64";

/// Prints one batch: total ms, min/avg/max us, hits, hash.
void printSpeedTestBatch(const SpeedTestBatch& batch);

/// Runs the speed test on 1 thread and, when options.threads > 1, again on
/// that many threads; prints both and the speed-up. Returns false when the
/// hashes of the two runs differ (a bug).
bool runAndPrintSpeedTest(const CollisionModel& model, const TraceModel& trm, const std::string& trmSpec,
                          const SpeedTestOptions& options);

}  // namespace cmkit::cli
