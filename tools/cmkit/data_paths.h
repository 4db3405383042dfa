// Where the CLI finds its data (the bundled map, the built web viewer): in
// an installed tree beside the running binary (PREFIX/bin/cmkit ->
// PREFIX/share/cmkit), else in the source tree around a build-tree binary
// (SRC/build/PRESET/bin/cmkit), found from the binary's own path. The binary
// holds no path of the tree it was built from (README, "Using the library":
// builds are reproducible).
#pragma once

#include <filesystem>

namespace cmkit::cli {

/// PREFIX/share/cmkit for a binary running from PREFIX/bin, when that
/// folder exists; empty otherwise (a build-tree binary).
std::filesystem::path installedDataDir();

/// The first `dir / relative` that exists, for dir the running binary's
/// folder and each folder above it (a build-tree binary finds the source
/// tree's files this way); empty when there is none.
std::filesystem::path findAboveExecutable(const std::filesystem::path& relative);

}  // namespace cmkit::cli
