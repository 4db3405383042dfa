// Loading the models named on a command line: a .cm file, or a .map file
// whose entities are built into models.
#pragma once

#include <string>
#include <vector>

#include "cmkit/materials.h"
#include "cmkit/model.h"
#include "cmkit/result.h"

namespace cmkit::cli {

/// Reads FILE.cm or builds every model of FILE.map (materials from
/// `materialsDir` when not empty, else the default rules).
Result<std::vector<ModelPtr>> loadModelsForCli(const std::string& path, const std::string& materialsDir);

}  // namespace cmkit::cli
