#!/bin/sh
# Builds Jolt Physics (cmkit_peers' optional peer) from ../shared/peers/jolt-5.5.0
# as its SOURCE.txt says, and installs it into build/jolt-prefix of the tree this
# script is in, where bench/CMakeLists.txt looks for it. Never part of the
# library or its package; CI does not run this. About 3-4 minutes on 2 cores.
#   bench/peers/build_jolt.sh [JOBS]   (default 2)
set -eu
tree=$(cd "$(dirname "$0")/../.." && pwd)
source="$tree/../shared/peers/jolt-5.5.0"
if [ ! -d "$source/Build" ]; then
  echo "build_jolt.sh: no Jolt source at $source: cmkit_peers will be built without Jolt"
  exit 0
fi
launcher=""
if command -v ccache >/dev/null 2>&1; then launcher="-DCMAKE_CXX_COMPILER_LAUNCHER=ccache"; fi
cmake -S "$source/Build" -B "$tree/build/jolt" -G Ninja -DCMAKE_BUILD_TYPE=Release $launcher \
  -DDOUBLE_PRECISION=OFF -DGENERATE_DEBUG_SYMBOLS=OFF \
  -DDEBUG_RENDERER_IN_DEBUG_AND_RELEASE=OFF -DPROFILER_IN_DEBUG_AND_RELEASE=OFF \
  -DFLOATING_POINT_EXCEPTIONS_ENABLED=OFF -DENABLE_OBJECT_STREAM=OFF \
  -DTARGET_UNIT_TESTS=OFF -DTARGET_HELLO_WORLD=OFF -DTARGET_PERFORMANCE_TEST=OFF \
  -DTARGET_SAMPLES=OFF -DTARGET_VIEWER=OFF -DCMAKE_INSTALL_PREFIX="$tree/build/jolt-prefix"
cmake --build "$tree/build/jolt" -j"${1:-2}" --target Jolt
cmake --install "$tree/build/jolt"
echo "build_jolt.sh: Jolt installed in $tree/build/jolt-prefix (reconfigure the build to use it)"
