// Fuzz target: .cm text -> reader -> models (validated) -> queries, and the
// writer's output read back (what cmkit writes it must read).
#include <cstdio>
#include <cstdlib>

#include "cmkit/cm_file.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > cmkit::fuzz::kMaxInputBytes) return 0;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto file = cmkit::parseCmText(text, "fuzz.cm", cmkit::MaterialTable{});
  if (!file) return 0;
  for (const cmkit::ModelPtr& m : file->models) cmkit::fuzz::requireValid(*m, "the .cm reader");
  cmkit::fuzz::exerciseModels(file->models);
  const std::string written = cmkit::writeCmText(file->models, file->crc);
  auto again = cmkit::parseCmText(written, "rewritten.cm", cmkit::MaterialTable{});
  if (!again || again->models.size() != file->models.size()) {
    std::fprintf(stderr, "a written .cm does not read back: %s\n",
                 again ? "model count differs" : again.error().toString().c_str());
    std::abort();
  }
  return 0;
}
