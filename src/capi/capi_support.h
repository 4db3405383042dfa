// What the C API's files share (src/capi: cmkit_c.cpp the errors, worlds
// and trace models; capi_queries.cpp the queries and batches; capi_player.cpp
// the player): the handles' definitions, the thread's error message and
// query scratch, the exception guard and the conversions between float
// arrays and cmkit's types. Private to src/capi.
#pragma once

#include <exception>
#include <new>
#include <string>
#include <utility>

#include "cmkit/cmkit.h"
#include "cmkit/movement.h"
#include "cmkit/world.h"

struct cmkit_world {
  cmkit::World world;
};

struct cmkit_trace_model {
  cmkit::TraceModel trm;
};

struct cmkit_player {
  cmkit::PlayerShape shape;
  cmkit::PlayerState state;
};

namespace cmkit::detail::capi {

// The calling thread's last error and its query scratch: each thread has its
// own, so concurrent queries share nothing.
inline thread_local std::string tLastError;

inline cmkit::WorldQueryWork& threadWork() {
  thread_local cmkit::WorldQueryWork work;
  return work;
}

inline cmkit_status fail(cmkit_status status, std::string message) {
  tLastError = std::move(message);
  return status;
}

inline cmkit_status failWith(const cmkit::Error& error, cmkit_status status = CMKIT_ERROR_INVALID_ARGUMENT) {
  return fail(status, error.toString());
}

// Runs `body` with every exception turned into a status.
template <class F>
inline cmkit_status guarded(const char* function, F&& body) {
  try {
    return body();
  } catch (const std::bad_alloc&) {
    return fail(CMKIT_ERROR_OUT_OF_MEMORY, std::string(function) + ": out of memory");
  } catch (const std::exception& e) {
    return fail(CMKIT_ERROR_INTERNAL, std::string(function) + ": " + e.what());
  } catch (...) {
    return fail(CMKIT_ERROR_INTERNAL, std::string(function) + ": unknown exception");
  }
}

// A C function's body: `fn` names the function in messages (inside the
// lambda __func__ would name the lambda).
#define CMKIT_API_BODY             \
  const char* const fn = __func__; \
  return ::cmkit::detail::capi::guarded(fn, [&]() -> cmkit_status

#define CMKIT_REQUIRE(pointer)                                                        \
  do {                                                                                \
    if ((pointer) == nullptr)                                                         \
      return ::cmkit::detail::capi::fail(CMKIT_ERROR_INVALID_ARGUMENT,                \
                                         std::string(fn) + ": " #pointer " is NULL"); \
  } while (false)

inline Vec3 vec(const float v[3]) { return Vec3(Real(v[0]), Real(v[1]), Real(v[2])); }

inline void put(float out[3], const Vec3& v) {
  out[0] = float(v.x);
  out[1] = float(v.y);
  out[2] = float(v.z);
}

inline cmkit::Mat3 axisOrIdentity(const float axis[9]) {
  cmkit::Mat3 m;
  if (axis != nullptr)
    for (int r = 0; r < 3; ++r) m.rows[r] = vec(axis + 3 * r);
  return m;
}

inline void putAxis(float out[9], const cmkit::Mat3& m) {
  for (int r = 0; r < 3; ++r) put(out + 3 * r, m.rows[r]);
}

inline const cmkit::TraceModel* trmOf(const cmkit_trace_model_t* trm) {
  return trm != nullptr ? &trm->trm : nullptr;
}

inline cmkit_status refused(cmkit::QueryStatus status, const char* function) {
  return fail(CMKIT_ERROR_REFUSED, std::string(function) + ": refused: " + cmkit::toString(status));
}

}  // namespace cmkit::detail::capi
