// Micro-benchmarks of the math and trace model building blocks.
#include <benchmark/benchmark.h>

#include "cmkit/math.h"
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

}  // namespace
