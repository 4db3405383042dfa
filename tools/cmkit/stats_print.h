// Statistics of collision models, printed as the original's PrintModelInfo
// does (counts with their memory in KB, per model and in total), or as JSON.
// Used by `cmkit compile` and `cmkit info` (for .map and .cm files alike).
#pragma once

#include <cstdio>
#include <span>
#include <string>

#include "cmkit/model.h"

namespace cmkit::cli {

/// The counts the original prints for one model, and the memory the
/// original's 64-bit structures would take for them.
struct ModelCounts {
  long long vertices = 0;
  long long edges = 0;  ///< including the dummy edge 0, as the original counts
  long long polygons = 0;
  long long brushes = 0;
  long long nodes = 0;  ///< without the root, as the original counts
  long long polygonRefs = 0;
  long long brushRefs = 0;
  long long internalEdges = 0;
  long long sharpEdges = 0;
  long long containedPolygonsRemoved = 0;
  long long polygonsMerged = 0;
  // bytes in the original's structures (64-bit build)
  long long vertexBytes = 0;
  long long edgeBytes = 0;
  long long polygonBytes = 0;
  long long brushBytes = 0;
  long long nodeBytes = 0;
  long long polygonRefBytes = 0;
  long long brushRefBytes = 0;
  long long totalBytes = 0;

  ModelCounts& operator+=(const ModelCounts& o);
};

/// Counts of one model.
ModelCounts countModel(const CollisionModel& model);

/// What the statistics describe besides the models.
struct StatsContext {
  std::string source;           ///< the file the models come from
  long long milliseconds = -1;  ///< time to build or load; < 0: not printed
  long long entities = -1;      ///< entities in the map; < 0: not printed
  bool perModel = true;         ///< also print every model
  bool cmkitMemory = false;     ///< text: also the memory the models take in cmkit
  std::string procFile;         ///< the .proc that pruned the world; empty: none
};

/// Prints the statistics in the original's layout ("collision data:", the
/// totals, then "model N "name": bounds (...)-(...) contents C" and its counts).
void printStatsText(std::FILE* out, std::span<const ModelPtr> models, const StatsContext& context);

/// The same statistics as one JSON object (for scripts).
std::string statsJson(std::span<const ModelPtr> models, const StatsContext& context);

/// A JSON string literal of s (quotes, backslashes and control characters
/// escaped).
std::string jsonString(const std::string& s);

}  // namespace cmkit::cli
