// Loading .cm files: lt4.cm (5.4 MB, 227 models) from the shared reference
// data, parsed from memory (the file read is not timed). Skips when the
// shared data is absent.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cmkit/cm_file.h"

namespace {

std::string readLt4(benchmark::State& state) {
  const std::filesystem::path path =
      std::filesystem::path(CMKIT_SOURCE_DIR) / ".." / "shared" / "reference" / "lt4.cm";
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    state.SkipWithError("../shared/reference/lt4.cm is absent (shared data not beside the clone); skipped");
    return {};
  }
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void BM_CmLoadLt4(benchmark::State& state) {
  const std::string text = readLt4(state);
  if (text.empty()) return;
  const cmkit::MaterialTable materials;
  std::size_t models = 0;
  for (auto _ : state) {
    cmkit::Result<cmkit::CmFile> f = cmkit::parseCmText(text, "lt4.cm", materials);
    if (!f) {
      state.SkipWithError(f.error().toString().c_str());
      return;
    }
    models = f->models.size();
    benchmark::DoNotOptimize(f);
  }
  state.counters["models"] = double(models);
  state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(text.size()));
}
BENCHMARK(BM_CmLoadLt4)->Unit(benchmark::kMillisecond);

void BM_CmWriteLt4(benchmark::State& state) {
  const std::string text = readLt4(state);
  if (text.empty()) return;
  cmkit::Result<cmkit::CmFile> f = cmkit::parseCmText(text, "lt4.cm", cmkit::MaterialTable{});
  if (!f) {
    state.SkipWithError(f.error().toString().c_str());
    return;
  }
  for (auto _ : state) {
    std::string out = cmkit::writeCmText(f->models, f->crc);
    benchmark::DoNotOptimize(out);
  }
  state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(text.size()));
}
BENCHMARK(BM_CmWriteLt4)->Unit(benchmark::kMillisecond);

}  // namespace
