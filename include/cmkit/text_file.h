// text_file.h: reading a whole input file, never throwing.
//
// Every loader of cmkit (.map, .mtr, .cm, and the CLI's query and result
// files) reads its file with readTextFile, so they all fail the same way:
// an Error naming the file and saying why, for a path that does not exist, a
// directory, a file that cannot be opened or read, or one too large to hold
// in memory. Nothing is thrown (not even std::bad_alloc).
#pragma once

#include <cstddef>
#include <limits>
#include <string>

#include "cmkit/result.h"

namespace cmkit {

/// The bytes of the file at `path` (as they are: a UTF-8 byte-order mark is
/// left for the readers, which skip it), at most `maxBytes` of them from the
/// start, or an Error with `path` as its file.
Result<std::string> readTextFile(const std::string& path,
                                 std::size_t maxBytes = std::numeric_limits<std::size_t>::max());

/// The bytes of standard input up to its end (at most `maxBytes`), or an
/// Error with "-" as its file; the command-line tools' "-" argument.
Result<std::string> readStandardInput(std::size_t maxBytes = std::numeric_limits<std::size_t>::max());

}  // namespace cmkit
