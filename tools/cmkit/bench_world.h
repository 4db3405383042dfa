// `cmkit bench MAP --world` (bench_world.cpp): the World's cost on queries
// with no entity near, against the world model alone.
#pragma once

#include <string>

namespace cmkit::cli {

/// What bench --world runs.
struct WorldBenchOptions {
  std::string map;        ///< the .map
  std::string materials;  ///< --materials
  bool noProc = false;    ///< --no-proc
  std::string trm;        ///< --trm
  int times = 2000;       ///< moves kept (--times)
  double length = 128;    ///< end within +-length per axis (--length)
  unsigned seed = 1;      ///< --seed
  int rounds = 15;        ///< --rounds
};

/// Runs it and prints the figures; 0, or 1 when a world answer differed
/// from the world model's (it must not, with no entity near).
int runWorldBench(const WorldBenchOptions& o);

}  // namespace cmkit::cli
