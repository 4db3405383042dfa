#!/usr/bin/env bash
# compare_mesh_builds.sh CLI_A CLI_B DIR: compiles every .obj in DIR (random_meshes.py writes
# them, with DIR/mtr) with both CLIs, with and without --robust-edges, and reports each mesh
# whose .cm files or exit codes differ. For changes to the mesh build that must keep its
# output: the cluster meshes take a minute or two each.
#
#   python3 tests/fidelity/random_meshes.py /tmp/meshes
#   tests/fidelity/compare_mesh_builds.sh /tmp/cmkit-before build/release/bin/cmkit /tmp/meshes
set -uo pipefail
a=$(realpath "$1")
b=$(realpath "$2")
dir=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n=0
different=0
for mesh in "$dir"/*.obj; do
  for opt in "" "--robust-edges"; do
    "$a" compile "$mesh" --materials "$dir/mtr" -o "$work/a.cm" $opt >/dev/null 2>&1
    ra=$?
    "$b" compile "$mesh" --materials "$dir/mtr" -o "$work/b.cm" $opt >/dev/null 2>&1
    rb=$?
    n=$((n + 1))
    if [ "$ra" != "$rb" ] || { [ "$ra" = 0 ] && ! cmp -s "$work/a.cm" "$work/b.cm"; }; then
      echo "different: $(basename "$mesh") $opt (exit codes $ra, $rb)"
      different=$((different + 1))
    fi
    rm -f "$work/a.cm" "$work/b.cm"
  done
done
echo "$n builds compared, $different different"
[ "$different" = 0 ]
