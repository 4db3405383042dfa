// CMKIT_ASSERT (src/util/assert.h): on in Debug and sanitizer builds, where a
// broken invariant stops the program with its condition, file and line; off
// (not evaluated) in release builds.
#include <gtest/gtest.h>

#include "util/assert.h"

namespace cmkit {
namespace {

TEST(Assert, OnInDebugAndSanitizerBuilds) {
  // CMKIT_TEST_EXPECT_ASSERTS: 1 when the build type is Debug or a sanitizer
  // is on (tests/CMakeLists.txt), where the presets turn CMKIT_ASSERTS on.
  EXPECT_EQ(detail::kAssertsEnabled, CMKIT_TEST_EXPECT_ASSERTS == 1);
}

TEST(Assert, AFalseConditionStopsWithItsTextWhereOn) {
  int evaluated = 0;
  const auto check = [&](bool holds) {
    ++evaluated;
    return holds;
  };
  CMKIT_ASSERT(check(true));
  if constexpr (detail::kAssertsEnabled) {
    EXPECT_EQ(evaluated, 1);
    GTEST_FLAG_SET(death_test_style, "threadsafe");
    EXPECT_DEATH(CMKIT_ASSERT(check(1 + 1 == 3)), "assertion failed: check\\(1 \\+ 1 == 3\\)");
  } else {
    EXPECT_EQ(evaluated, 0);  // not evaluated
  }
}

}  // namespace
}  // namespace cmkit
