// `cmkit trm SPEC`: build a trace model and print it.
#include <fmt/core.h>

#include <cstdlib>

#include "cmkit/trace_model.h"
#include "commands.h"
#include "option_checks.h"

namespace cmkit::cli {

void registerTrm(CLI::App& app) {
  auto* cmd =
      app.add_subcommand("trm",
                         "Build a trace model (a shape to move through the world) and print its vertices,\n"
                         "edges, polygons, bounds and mass properties.\n\n"
                         "SPEC is one of:\n"
                         "  point\n"
                         "  box:x0,y0,z0,x1,y1,z1            axis-aligned box (min then max)\n"
                         "  octahedron:x0,y0,z0,x1,y1,z1     vertices at the face centres of the bounds\n"
                         "  dodecahedron:x0,y0,z0,x1,y1,z1   scaled to the bounds\n"
                         "  cylinder:N:x0,y0,z0,x1,y1,z1     N = 3..10 sides\n"
                         "  cone:N:x0,y0,z0,x1,y1,z1         N = 3..15 sides, apex at the top\n"
                         "  bone:length,width                two tetrahedra along z\n"
                         "  polygon:x,y,z;x,y,z;...          planar convex polygon, counter-clockwise\n"
                         "  polygonvolume:T:x,y,z;...        polygon extruded backwards by T\n"
                         "  hull:x,y,z;x,y,z;...             convex hull of the points\n\n"
                         "Example: cmkit trm box:-16,-16,0,16,16,72");
  auto spec = std::make_shared<std::string>();
  auto density = std::make_shared<double>(1.0);
  cmd->add_option("SPEC", *spec, "the trace model")->required();
  cmd->add_option("--density", *density, "density for the mass properties")
      ->capture_default_str()
      ->check(finiteAtLeast(0));
  cmd->callback([spec, density] {
    auto trm = TraceModel::parse(*spec);
    if (!trm) {
      fmt::print(stderr, "cmkit trm: {}\n", trm.error().toString());
      std::exit(kExitBadInput);
    }
    fmt::print("{}", trm->describe());
    const MassProperties mp = trm->massProperties(Real(*density));
    fmt::print("mass properties (density {}): volume {:g}, mass {:g}, centre of mass ({:g} {:g} {:g})\n",
               *density, mp.volume, mp.mass, mp.centerOfMass.x, mp.centerOfMass.y, mp.centerOfMass.z);
    fmt::print("inertia tensor about the centre of mass:\n");
    for (int r = 0; r < 3; ++r) {
      fmt::print("  ({:g} {:g} {:g})\n", mp.inertiaTensor[r].x, mp.inertiaTensor[r].y, mp.inertiaTensor[r].z);
    }
    if (const std::string bad = trm->checkInvariants(); !bad.empty() && !trm->isPoint()) {
      fmt::print("warning: {}\n", bad);
    }
  });
}

}  // namespace cmkit::cli
