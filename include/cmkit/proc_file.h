// proc_file.h: the renderer's BSP of a .proc file, as the collision code
// reads it (the original's LoadProcBSP): only the `nodes` section matters.
//
// A map compiler writes NAME.proc beside NAME.map. When it is there, the
// original drops every solid polygon winding of the world model that lies
// entirely in opaque solid leaves of this tree (BuildOptions::procBsp,
// docs/algorithms.md, "Building a model").
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/plane.h"
#include "cmkit/result.h"

namespace cmkit {

/// One node of the .proc BSP.
struct ProcNode {
  /// The split plane; the front (children[0]) side is distance > 0. The file
  /// holds it as ( a b c d ) with a*x + b*y + c*z + d = 0, so dist = -d.
  Plane plane;
  /// Front and back child: > 0 another node (always a later one), 0 an
  /// opaque solid leaf, < 0 the area -1 - child.
  std::int32_t children[2] = {0, 0};
};

/// The `nodes` section of a .proc file. Node 0 is the root.
struct ProcBsp {
  std::string fileName;  ///< for messages
  /// Empty when the file has no `nodes` section (or an unknown header, which
  /// the original only warns about): nothing is pruned then.
  std::vector<ProcNode> nodes;

  /// True when there is a tree to prune with.
  bool usable() const { return !nodes.empty(); }
};

/// Parses .proc text ("mapProcFile003", then sections; `model`,
/// `shadowModel` and `interAreaPortals` are skipped, `nodes` is read and ends
/// the parse). A wrong header gives a warning (appended to `warnings` when not
/// null) and an empty tree, as the original; any other malformed input, a
/// child number outside the tree or a child that is not a later node (the
/// walk could loop) is an Error with file:line:column.
Result<ProcBsp> parseProcText(std::string_view text, std::string fileName = "<proc>",
                              std::vector<std::string>* warnings = nullptr);

/// Reads and parses a .proc file (errors as parseProcText; a file that
/// cannot be opened is an Error).
Result<ProcBsp> loadProcFile(const std::string& path, std::vector<std::string>* warnings = nullptr);

/// NAME.proc for NAME.map (the extension replaced; appended when there is none).
std::string procPathForMap(const std::string& mapPath);

/// NAME.proc beside the map when it exists (loaded and parsed as
/// loadProcFile), nullopt when there is none.
Result<std::optional<ProcBsp>> loadProcFileForMap(const std::string& mapPath,
                                                  std::vector<std::string>* warnings = nullptr);

}  // namespace cmkit
