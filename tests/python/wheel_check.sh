#!/bin/sh
# `pip wheel` / `pip install` from a fresh copy of the tree (ctest
# python_wheel): copies the files of SRC that git tracks or would track (not
# ignored) to WORK/src, makes the wheel there with `PY -m pip wheel --no-build-isolation` (no network), installs it
# with --target and into a venv made with --system-site-packages, and from a
# third folder loads a map and answers a batch of point contents with each.
# The wheel's extension module is built by CMake as setup.py says; here
# CMKIT_CMAKE_BUILD_DIR=BUILD hands it this build's already built module, so
# the test costs no second compile (`./dev.sh wheel` builds from nothing).
#   tests/python/wheel_check.sh PY SRC WORK BUILD
set -eu
py=$1 src=$2 work=$3 build=$4
rm -rf "$work"
mkdir -p "$work/src" "$work/elsewhere"
if git -C "$src" rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  (cd "$src" && git ls-files -z --cached --others --exclude-standard | xargs -0 tar cf -) | (cd "$work/src" && tar xf -)
else
  (cd "$src" && tar cf - --exclude=./build --exclude=./viewer/node_modules .) | (cd "$work/src" && tar xf -)
fi
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_ROOT_USER_ACTION=ignore PYTHONDONTWRITEBYTECODE=1
CMKIT_CMAKE_BUILD_DIR=$build "$py" -m pip wheel --no-build-isolation --no-deps -q -w "$work/wheel" "$work/src"
wheel=$(ls "$work"/wheel/cmkit-*.whl)
echo "wheel: $(basename "$wheel")"
"$py" -m pip install --no-deps -q --target "$work/target" "$wheel"
"$py" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/python" -m pip install --no-deps -q "$wheel"
check='
import sys, numpy as np, cmkit
models = cmkit.load_map(sys.argv[1])
world = models[0]
lo, hi = world.bounds
points = np.stack([np.linspace(lo[i], hi[i], 1000) for i in range(3)], axis=1)
contents = world.point_contents(points)["contents"]
assert contents.shape == (1000,) and (contents != 0).any() and (contents == 0).any(), contents
print(cmkit.__file__, len(models), "models,", int((contents != 0).sum()), "of 1000 points in a brush")
'
map="$work/src/data/maps/lt4/lt4.map"
cd "$work/elsewhere"
PYTHONPATH="$work/target" "$py" -c "$check" "$map" | grep -F "$work/target/cmkit/"
"$work/venv/bin/python" -c "$check" "$map" | grep -F "$work/venv/"
