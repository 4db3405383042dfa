// Internal: CMKIT_ASSERT(condition) checks an invariant of the library's own
// making (not the caller's input: that is refused with a Result or a
// QueryStatus, never asserted). On in builds configured with CMKIT_ASSERTS
// (the default of Debug builds and of the sanitizer presets), where a false
// condition prints the condition, file and line and aborts; off in release
// builds, where the condition is not evaluated (it is still compiled, so it
// cannot rot).
#pragma once

namespace cmkit::detail {

/// Prints "cmkit: assertion failed: CONDITION (FILE:LINE)" to stderr and aborts.
[[noreturn]] void assertFailed(const char* condition, const char* file, int line);

/// Whether this build checks CMKIT_ASSERT conditions.
#ifdef CMKIT_ASSERTS
inline constexpr bool kAssertsEnabled = true;
#else
inline constexpr bool kAssertsEnabled = false;
#endif

}  // namespace cmkit::detail

#ifdef CMKIT_ASSERTS
#define CMKIT_ASSERT(condition) \
  ((condition) ? void(0) : ::cmkit::detail::assertFailed(#condition, __FILE__, __LINE__))
#else
#define CMKIT_ASSERT(condition) ((void)sizeof(!(condition)))
#endif
