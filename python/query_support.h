// query_support.h: what the batch queries of cmkit.Model (query_bindings.cpp)
// and of cmkit.World (world_bindings.cpp) share, so that the two take the
// same arguments and give the same dicts: each kind's arguments converted
// from Python with the GIL held (the *Args structs: the batch and the arrays
// its spans point into), the progress hook and the run without the GIL, and
// the dicts of numpy arrays made from the answers (query_bindings.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "cmkit/batch.h"
#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "module_support.h"

namespace cmkit_python {

// ---- running a batch ----------------------------------------------------

// Batch options with the progress hook: the Python callable (if any) is
// called with the GIL; Ctrl-C (a pending signal) cancels the batch. Made in
// place (the hook points at it).
struct Hook {
  py::object callback;
  cmkit::BatchOptions options;

  Hook(int threads, py::object cb);
  Hook(const Hook&) = delete;
  Hook& operator=(const Hook&) = delete;
};

// Runs a batch without the GIL; a Python exception from the hook (or a
// signal) wins over the batch's "cancelled" error.
template <class F>
void runBatch(F&& run) {
  cmkit::Status s = cmkit::Ok{};
  {
    py::gil_scoped_release release;
    s = run();
  }
  if (PyErr_Occurred()) throw py::error_already_set();
  if (!s.ok()) raise(s.error());
}

// ---- the arguments of each kind, checked --------------------------------
// Each holds the batch (its `query.placement` left at the identity for the
// caller to set) and `size`, the number of answers. Not copyable: the batch's
// spans point into the struct.

struct NoCopy {
  NoCopy() = default;
  NoCopy(const NoCopy&) = delete;
  NoCopy& operator=(const NoCopy&) = delete;
};

// translate(trm, starts, ends, mask, axis, start_solid).
struct TranslationArgs : NoCopy {
  TrmArg trm;
  std::vector<Vec3> starts, ends;
  cmkit::TranslationBatch batch;
  std::size_t size = 0;
  TranslationArgs(const py::object& trmObject, const py::object& startsObject, const py::object& endsObject,
                  std::int64_t mask, const py::object& axis, bool startSolid);
};

// rotate(trm, starts, origins, axes, angles, mask, axis, start_solid).
struct RotationArgs : NoCopy {
  TrmArg trm;
  std::vector<Vec3> starts;
  std::vector<cmkit::Rotation> rotations;
  cmkit::RotationBatch batch;
  std::size_t size = 0;
  RotationArgs(const py::object& trmObject, const py::object& startsObject, const py::object& origins,
               const py::object& axes, const py::object& angles, std::int64_t mask, const py::object& axis,
               bool startSolid);
};

// cast_rays(origins, ends, mask).
struct RayArgs : NoCopy {
  std::vector<Vec3> starts, ends;
  cmkit::RayBatch batch;
  std::size_t size = 0;
  RayArgs(const py::object& origins, const py::object& endsObject, std::int64_t mask);
};

// point_contents(points).
struct PointArgs : NoCopy {
  std::vector<Vec3> points;
  cmkit::PointContentsBatch batch;
  std::size_t size = 0;
  explicit PointArgs(const py::object& pointsObject);
};

// contents(trm, positions, mask, axis).
struct ContentsArgs : NoCopy {
  TrmArg trm;
  std::vector<Vec3> positions;
  cmkit::ContentsBatch batch;
  std::size_t size = 0;
  ContentsArgs(const py::object& trmObject, const py::object& positionsObject, std::int64_t mask,
               const py::object& axis);
};

// contacts(trm, starts, dirs, depth, max_contacts, origins, axes, angles,
// mask, axis).
struct ContactsArgs : NoCopy {
  TrmArg trm;
  std::vector<Vec3> starts, dirs;
  std::vector<cmkit::Rotation> rotations;
  cmkit::ContactsBatch batch;
  std::size_t size = 0;
  ContactsArgs(const py::object& trmObject, const py::object& startsObject, const py::object& dirsObject,
               double depth, int maxContacts, const py::object& origins, const py::object& axes,
               const py::object& angles, std::int64_t mask, const py::object& axis);
};

// ---- the answers as dicts of numpy arrays -------------------------------

// The (N,) uint8 array of the results' QueryStatus values (STATUS_*).
template <class R>
py::array_t<std::uint8_t> statusArray(const std::vector<R>& results) {
  auto status = py::array_t<std::uint8_t>(py::ssize_t(results.size()));
  for (std::size_t i = 0; i < results.size(); ++i) status.mutable_data()[i] = std::uint8_t(results[i].status);
  return status;
}

// translate() and rotate(): fraction, endpos, endaxis, start_solid, status
// and the contact's fields.
py::dict traceArrays(const std::vector<cmkit::TraceResult>& results);
// cast_rays(): fraction, endpos, normal, dist, contents, material, polygon, hit.
py::dict rayArrays(const std::vector<cmkit::RayHit>& hits);
// point_contents(): contents, status.
py::dict pointContentsArrays(const std::vector<std::uint32_t>& contents,
                             const std::vector<cmkit::QueryStatus>& status);
// contents(): contents, status, the trace fields (contact_contents).
py::dict contentsArrays(const std::vector<cmkit::ContentsResult>& results);
// contacts(): count, status, the contact fields (N, maxContacts, ...), angle.
py::dict contactsArrays(const std::vector<cmkit::ContactsResult>& results, int maxContacts);

// The docstrings' shared closing note on threads, progress and precision.
extern const char* const kBatchNote;

}  // namespace cmkit_python
