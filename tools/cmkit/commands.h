// The cmkit command-line tool: one file per command, each registering itself
// on the CLI11 application. main.cpp lists them.
#pragma once

#include <CLI/CLI.hpp>

namespace cmkit::cli {

/// `cmkit trm SPEC`: builds a trace model and prints its features.
void registerTrm(CLI::App& app);

/// `cmkit query MODELS QUERIES`: runs a query file (docs/query-format.md).
void registerQuery(CLI::App& app);

/// `cmkit compile MAP`: builds the collision models of a map, prints their
/// statistics, optionally writes a .cm file.
void registerCompile(CLI::App& app);

/// `cmkit info FILE`: statistics of the collision models of a file.
void registerInfo(CLI::App& app);

/// `cmkit validate FILE`: checks the invariants of every model of a .cm or .map.
void registerValidate(CLI::App& app);

/// `cmkit render MODELS -o out.png`: a picture of the models (and traces).
void registerRender(CLI::App& app);

/// `cmkit export MODELS -o out.gltf|.glb|.obj`: the models (and traces) as a 3D file.
void registerExport(CLI::App& app);

/// `cmkit view MODELS`: serves the web viewer on a loopback address.
void registerView(CLI::App& app);

/// `cmkit bench MODELS`: the original's collision speed test; `--suite DIR`.
void registerBench(CLI::App& app);

/// `cmkit soak MAP`: random sweeps and a walker, every end checked.
void registerSoak(CLI::App& app);

/// `cmkit walk MAP`: a player walked through a map's World (movement.h).
void registerWalk(CLI::App& app);

/// `cmkit audit MAP`: reachability of a player and the map's faults (audit.h).
void registerAudit(CLI::App& app);

/// `cmkit demo [MAP]`: compile, speed test and picture of the bundled map.
void registerDemo(CLI::App& app);

/// Exit code for bad input (files, arguments) as opposed to 0 = success.
inline constexpr int kExitBadInput = 2;
/// Exit code of `cmkit query` when it wrote every result line but some are
/// error=REASON.
inline constexpr int kExitQueryErrors = 3;

}  // namespace cmkit::cli
