// The installed data folder of the running binary: see data_paths.h.
#include "data_paths.h"

namespace cmkit::cli {

std::filesystem::path installedDataDir() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  const fs::path share = (exe.parent_path() / ".." / "share" / "cmkit").lexically_normal();
  return fs::is_directory(share, ec) ? share : fs::path{};
}

}  // namespace cmkit::cli
