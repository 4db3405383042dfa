// The data folders of the running binary: see data_paths.h.
#include "data_paths.h"

namespace cmkit::cli {

namespace {

std::filesystem::path executablePath() {
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path{} : exe;
}

}  // namespace

std::filesystem::path installedDataDir() {
  namespace fs = std::filesystem;
  const fs::path exe = executablePath();
  if (exe.empty()) return {};
  std::error_code ec;
  const fs::path share = (exe.parent_path() / ".." / "share" / "cmkit").lexically_normal();
  return fs::is_directory(share, ec) ? share : fs::path{};
}

std::filesystem::path findAboveExecutable(const std::filesystem::path& relative) {
  namespace fs = std::filesystem;
  const fs::path exe = executablePath();
  std::error_code ec;
  for (fs::path dir = exe.parent_path(); !dir.empty(); dir = dir.parent_path()) {
    const fs::path candidate = dir / relative;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal();
    if (dir == dir.root_path()) break;
  }
  return {};
}

}  // namespace cmkit::cli
