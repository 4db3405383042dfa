// Checks of number options, shared by every command: a value that is not a
// finite number (nan, inf, 1e999) or is out of its range is refused while
// the command line is parsed, with a message naming the option, and the CLI
// exits with kExitBadInput (main.cpp) before any work is done.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string_view>

#include "cmkit/math.h"

namespace cmkit::cli {

/// A finite number (any sign).
CLI::Validator finiteNumber();

/// A finite number >= `lo`.
CLI::Validator finiteAtLeast(double lo);

/// "x,y,z": three finite numbers separated by commas, nothing else.
std::optional<Vec3> parseFiniteVec3(std::string_view text);

/// An option holding "x,y,z" (parseFiniteVec3).
CLI::Validator finiteVec3();

/// "x,y" or "x,y,z": two or three finite numbers separated by commas (z = 0
/// when absent).
std::optional<Vec3> parseFiniteVec2or3(std::string_view text);

/// An option holding "x,y" or "x,y,z" (parseFiniteVec2or3).
CLI::Validator finiteVec2or3();

}  // namespace cmkit::cli
