// ply_check.h: the check of a PLY file cmkit makes before assimp reads it.
//
// Debian 12's assimp (5.2) reads forever on some malformed PLY headers and
// reads past the end of binary PLY files whose data is shorter than their
// header says (both found by fuzzing; docs/reliability.md). cmkit checks the
// header by the format's grammar and walks the binary data's sizes first, so
// that a malformed file is an error naming the line, not a hang or a crash.
#pragma once

#include <string>
#include <string_view>

namespace cmkit {

/// Why a PLY file is malformed (the header line, or where its binary data
/// ends too soon), or an empty string when assimp can be given it. ASCII
/// data is left to assimp (its errors are errors, not crashes).
std::string plyProblem(std::string_view file);

}  // namespace cmkit
