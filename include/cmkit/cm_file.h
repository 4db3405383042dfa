// cm_file.h: .cm collision model files (the original's CM "1.00" text
// format, docs/cm-format.md): reading and writing.
//
// Reading follows the original loader (LoadCollisionModelFile):
//  - header `CM "1.00"`, the map's geometry CRC (unsigned, 0 = any map), then
//    any number of `collisionModel "NAME" { ... }` blocks. Names may repeat.
//  - sections `vertices`, `edges`, `nodes`, `polygons`, `brushes` in any
//    order (each at most once); the allocation hints after `polygons` and
//    `brushes` are accepted and ignored; C and C++ comments anywhere.
//  - numbers are converted exactly as the original lexer converts them, so
//    a loaded model is bit-identical to the original's.
//  - brush contents as comma-separated names or (old files) an integer.
// After a model is read:
//  - polygons and brushes are stored in file order; each is filtered into
//    the stored tree by its bounds and PREPENDED to the list of every node it
//    reaches (docs/cm-format.md), so node lists run in reverse file order, as in the
//    original after loading;
//  - polygon contents come from their material through the MaterialTable
//    (material names are stored canonical); brushes get no material (-1)
//    and primitive number 0, as in the original;
//  - edge normals, model bounds and contents are recomputed.
// A malformed file (truncated, a wrong token, an index out of range, a
// non-finite or out-of-range number, an edge referencing a missing vertex, a
// polygon with fewer than 3 edges, an unknown content name, a repeated
// section) gives an Error with file:line:column and no models at all.
//
// Writing produces what the original writes for the same model: numbers as
// the original's "%f" (10 decimals, trailing zeros and dot removed), the
// CRC on line 3, the same comments and memory-size hints. Polygons and
// brushes are written in stored (index) order, which for a built model is
// the original's order (tree pre-order, front child first, each item once);
// for a loaded model it reproduces the file it came from.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/result.h"

namespace cmkit {

/// The contents of a .cm file.
struct CmFile {
  /// The geometry CRC of the map the file was written for (0: any map).
  std::uint32_t crc = 0;
  /// The models in file order (model 0 is usually, not always, "worldMap").
  std::vector<ModelPtr> models;
};

/// Parses .cm text. `fileName` is used in error messages; `materials` gives
/// polygon contents. Either every model or an Error.
Result<CmFile> parseCmText(std::string_view text, std::string fileName, const MaterialTable& materials);

/// Reads and parses a .cm file.
Result<CmFile> loadCmFile(const std::string& path, const MaterialTable& materials);

/// Reads only the CRC on line 3 of a .cm file (cheap; used to decide whether
/// a .cm next to a map is up to date). Error if the header is malformed.
Result<std::uint32_t> readCmFileCrc(const std::string& path);

/// Options of writeCmText.
struct CmWriteOptions {
  /// Write the original's memory-size hints after `polygons` and `brushes`
  /// (`/* polygonMemory = */ N`, sizes of the original's 64-bit structs).
  /// The original's reader ignores them; so does cmkit's.
  bool memoryHints = true;
};

/// The .cm text of the models, with `crc` on line 3.
std::string writeCmText(std::span<const ModelPtr> models, std::uint32_t crc,
                        const CmWriteOptions& options = {});

/// Writes the models to a .cm file (replacing it). Error if it cannot be
/// written.
Status saveCmFile(const std::string& path, std::span<const ModelPtr> models, std::uint32_t crc,
                  const CmWriteOptions& options = {});

/// A number as the original's .cm writer prints a float ("%f" meaning 10
/// decimals, then trailing zeros and a trailing dot removed): 0.5, -0, 64,
/// 352.0000305176.
std::string formatCmFloat(float value);

}  // namespace cmkit
