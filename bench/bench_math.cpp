// Micro-benchmarks of the math and trace model building blocks, and of a
// query's fixed cost.
#include <benchmark/benchmark.h>

#include "cmkit/math.h"
#include "cmkit/model.h"
#include "cmkit/query.h"
#include "cmkit/trace_model.h"

namespace {

void BM_PermutedInnerProduct(benchmark::State& state) {
  const cmkit::Pluecker a = cmkit::Pluecker::fromLine({1, 2, 3}, {4, -5, 6});
  cmkit::Pluecker b = cmkit::Pluecker::fromRay({-1, 0.5f, 2}, {0.3f, 0.1f, -0.7f});
  for (auto _ : state) {
    benchmark::DoNotOptimize(b);
    benchmark::DoNotOptimize(a.permutedInnerProduct(b));
  }
}
BENCHMARK(BM_PermutedInnerProduct);

void BM_Normalize(benchmark::State& state) {
  cmkit::Vec3 v{3, 4, 12};
  for (auto _ : state) {
    benchmark::DoNotOptimize(v);
    cmkit::Vec3 n = v;
    benchmark::DoNotOptimize(n.normalize());
  }
}
BENCHMARK(BM_Normalize);

void BM_BuildBoxTraceModel(benchmark::State& state) {
  for (auto _ : state) {
    auto trm = cmkit::TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
    benchmark::DoNotOptimize(trm);
  }
}
BENCHMARK(BM_BuildBoxTraceModel);

void BM_BuildCylinderTraceModel(benchmark::State& state) {
  for (auto _ : state) {
    auto trm = cmkit::TraceModel::cylinder({{-16, -16, 0}, {16, 16, 72}}, 10);
    benchmark::DoNotOptimize(trm);
  }
}
BENCHMARK(BM_BuildCylinderTraceModel);

// A box translation that meets no polygon (the model is one box far off):
// what every translation pays before its first polygon, its set-up, guards
// and walk of a one-leaf tree. Argument 1: the box turned (a trace-model axis).
void BM_TranslationSetUp(benchmark::State& state) {
  const cmkit::TraceModel box = *cmkit::TraceModel::box({{-16, -16, 0}, {16, 16, 72}});
  const cmkit::ModelPtr far = cmkit::collisionModelFromTraceModel(
      *cmkit::TraceModel::box({{10000, 10000, 10000}, {10010, 10010, 10010}}));
  cmkit::QueryWork work;
  cmkit::TranslationQuery q{&box, {}, {0, 0, 0}, {100, 50, -20}, cmkit::contents::kMaskSolid, {}, false};
  if (state.range(0) != 0) q.trmAxis = cmkit::Mat3::fromAngles(10, 20, 30);
  int i = 0;
  for (auto _ : state) {
    q.start.x = cmkit::Real(i++ & 7);
    benchmark::DoNotOptimize(cmkit::translate(*far, q, work));
  }
}
BENCHMARK(BM_TranslationSetUp)->Arg(0)->Arg(1);

}  // namespace
