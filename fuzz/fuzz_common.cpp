#include "fuzz_common.h"

#include <algorithm>
#include <cstdio>
#include <vector>

#include "cmkit/query.h"
#include "cmkit/ray_index.h"
#include "cmkit/trace_model.h"
#include "cmkit/validate.h"

namespace cmkit::fuzz {

void requireValid(const CollisionModel& model, std::string_view where) {
  // Odd geometry is fine (odd input gives odd shapes, as in the original);
  // broken structure is a bug in whatever produced the model.
  for (const Violation& v : validateModel(model)) {
    if (v.kind != Violation::Kind::Structure) continue;
    std::fprintf(stderr, "%.*s produced a corrupt model: %s\n", int(where.size()), where.data(),
                 v.toString().c_str());
    std::abort();
  }
}

void exerciseModels(std::span<const ModelPtr> models) {
  QueryWork work;
  const TraceModel point = TraceModel::point();
  const auto box = TraceModel::box(Bounds{{-8, -8, -8}, {8, 8, 8}});
  // The first kMaxModelsExercised models only: a map of many entities
  // would otherwise spend a run's time on queries rather than on new input.
  constexpr std::size_t kMaxModelsExercised = 8;
  for (const ModelPtr& m : models.first(std::min(models.size(), kMaxModelsExercised))) {
    if (!m) continue;
    const RayIndex rays(*m);  // any model, even an empty one, can be indexed
    if (m->bounds().isCleared()) continue;
    const Vec3 lo = m->bounds().min, hi = m->bounds().max;
    const Vec3 mid = (lo + hi) * Real(0.5);
    // Moves across the bounds along each axis and a diagonal, point and box.
    const Vec3 ends[][2] = {{{lo.x - 16, mid.y, mid.z}, {hi.x + 16, mid.y, mid.z}},
                            {{mid.x, hi.y + 16, mid.z}, {mid.x, lo.y - 16, mid.z}},
                            {{mid.x, mid.y, hi.z + 16}, {mid.x, mid.y, lo.z - 16}},
                            {lo - Vec3{16, 16, 16}, hi + Vec3{16, 16, 16}}};
    for (const auto& e : ends) {
      for (const TraceModel* trm : {&point, box ? &*box : &point}) {
        TranslationQuery q;
        q.trm = trm;
        q.start = e[0];
        q.end = e[1];
        q.contentMask = ~0u;
        q.detectStartSolid = true;
        (void)translate(*m, q, work);
        ContentsQuery c{trm, Mat3::identity(), e[0], ~0u, {}};
        (void)contentsTest(*m, c, work);
        ContactsQuery k;
        k.trm = trm;
        k.start = e[0];
        k.dir = e[1] - e[0];
        k.depth = 1;
        k.contentMask = ~0u;
        (void)contacts(*m, k, work);
      }
      (void)pointContents(*m, {e[0], {}}, work);
      (void)rays.cast({e[0], e[1], ~0u});
    }
    if (box) {
      RotationQuery r;
      r.trm = &*box;
      r.start = mid;
      r.rotation = Rotation(mid + Vec3{0, 0, 24}, Vec3{1, 0, 0}, 90);
      r.contentMask = ~0u;
      (void)rotate(*m, r, work);
    }
  }
}

}  // namespace cmkit::fuzz
