// cmkit: collision models for id Tech 4 (Doom 3) level geometry.
#include <fmt/core.h>
#include <CLI/CLI.hpp>
#include <string>

#include "cmkit/config.h"
#include "commands.h"

int main(int argc, char** argv) {
  CLI::App app{
      "cmkit - collision models for id Tech 4 (Doom 3) level geometry.\n"
      "Builds trace models (the shapes you move) and collision models (from .map, .cm and mesh\n"
      "files), runs exact swept-shape queries against them, draws, exports and times them.\n"
      "Run 'cmkit COMMAND --help' for the options of a command."};
  app.require_subcommand(1);
  app.set_version_flag(
      "--version", fmt::format("cmkit {}.{}.{} ({} precision{})", cmkit::kVersionMajor, cmkit::kVersionMinor,
                               cmkit::kVersionPatch, cmkit::kDoublePrecision ? "double" : "float",
                               cmkit::kDoublePrecision ? ", CMKIT_DOUBLE" : ""));
  cmkit::cli::registerTrm(app);
  cmkit::cli::registerCompile(app);
  cmkit::cli::registerInfo(app);
  cmkit::cli::registerValidate(app);
  cmkit::cli::registerQuery(app);
  cmkit::cli::registerRender(app);
  cmkit::cli::registerExport(app);
  cmkit::cli::registerView(app);
  cmkit::cli::registerBench(app);
  cmkit::cli::registerSoak(app);
  cmkit::cli::registerWalk(app);
  cmkit::cli::registerAudit(app);
  cmkit::cli::registerDemo(app);
  // Exit codes: every command's --help ends with the ones it uses.
  app.footer(
      "Exit codes (every command): 0 success; 1 the work ran but a check failed (validate: violations;\n"
      "soak: a must-hold check; audit: a finding of high severity; demo, bench: threaded results differ\n"
      "from the single-thread ones);\n"
      "2 bad input or arguments (an unreadable or malformed file with file:line, an unknown option);\n"
      "3 query only: every result line written, but some are error=REASON.");
  // An unknown command is named as such (CLI11 alone would say that a
  // subcommand is required): `known` and `names` are gathered in the same loop.
  bool known = argc < 2 || argv[1][0] == '-';
  std::string names;
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    const std::string name = sub->get_name();
    names += (names.empty() ? "" : ", ") + name;
    known = known || name == argv[1];
    if (sub->get_description().find("Exit codes") != std::string::npos) continue;
    sub->footer(
        name == "demo" || name == "bench"
            ? "Exit codes: 0 success, 1 the threaded run's results differ from the single-thread run's,\n"
              "2 bad input or arguments."
            : "Exit codes: 0 success, 2 bad input or arguments (file:line: message).");
  }
  if (!known) {
    fmt::print(stderr,
               "cmkit: unknown command '{}'; the commands are: {}\nRun 'cmkit --help' for what each does.\n",
               argv[1], names);
    return cmkit::cli::kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every refused argument (an
    // unknown option, a missing file name, a value out of range) is bad
    // input, exit code 2 like a bad file.
    return app.exit(e) == 0 ? 0 : cmkit::cli::kExitBadInput;
  }
  return 0;
}
