// CMKIT_ASSERT's failure report (util/assert.h).
#include "util/assert.h"

#include <cstdio>
#include <cstdlib>

namespace cmkit::detail {

void assertFailed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "cmkit: assertion failed: %s (%s:%d)\n", condition, file, line);
  std::fflush(stderr);
  std::abort();
}

}  // namespace cmkit::detail
