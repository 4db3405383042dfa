// Where the CLI finds its data (the bundled map, the built web viewer): in
// an installed tree beside the running binary (PREFIX/bin/cmkit ->
// PREFIX/share/cmkit), else in the source tree the binary was built from.
#pragma once

#include <filesystem>

namespace cmkit::cli {

/// PREFIX/share/cmkit for a binary running from PREFIX/bin, when that
/// folder exists; empty otherwise (a build-tree binary).
std::filesystem::path installedDataDir();

}  // namespace cmkit::cli
