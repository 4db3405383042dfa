// mesh_checks.h: the checks of mesh files cmkit makes before assimp reads
// them.
//
// Debian 12's assimp (5.2) reads forever on some malformed PLY headers, reads
// past the end of binary PLY files whose data is shorter than their header
// says, and allocates what a GLB file's header claims (4 GB for a 2 KB file
// whose chunk length was garbled) (all found by fuzzing; docs/reliability.md).
// cmkit checks the PLY header by the format's grammar and walks its binary
// data's sizes, and checks a GLB file's lengths against its size first, so
// that a malformed file is an error that says what is wrong, not a hang, a
// crash or gigabytes of memory.
#pragma once

#include <string>
#include <string_view>

namespace cmkit {

/// Why a PLY file is malformed (the header line, or where its binary data
/// ends too soon), or an empty string when assimp can be given it. ASCII
/// data is left to assimp (its errors are errors, not crashes).
std::string plyProblem(std::string_view file);

/// Why a binary glTF file (one that starts with the magic "glTF") is
/// malformed: its total length or a chunk's length runs past the end of the
/// file, or a chunk header is cut off. Empty when it is well formed, or not
/// a binary glTF file at all (text glTF and other formats are left to
/// assimp).
std::string glbProblem(std::string_view file);

}  // namespace cmkit
