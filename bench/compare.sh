#!/usr/bin/env bash
# bench/compare.sh OLD_COMMIT [--suite DIR] [--repeat N] [--runs R]
#
# Speed of this tree against an older commit, measured in one run on this
# machine: builds OLD_COMMIT's CLI beside the tree (build/compare/<commit>),
# builds this tree's CLI (build/release), then runs `cmkit bench --suite DIR
# --repeat N` with each, alternating, R times, and prints per query kind and
# per reference file both sides' ns/query (best of the R runs) and the
# speed-up (old / new; above 1: this tree is faster), with the geometric mean
# over the files and the slowest file of each kind.
#
#   bench/compare.sh 9ad5b38                         # ../shared/reference, 20 passes, 3 runs
#   bench/compare.sh 9ad5b38 --suite ../shared/reference-proc --repeat 5 --runs 1
#
# Nothing is downloaded: the old commit comes from this repository's history.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

old="${1:-}"
if [ -z "$old" ] || [ "$old" = "-h" ] || [ "$old" = "--help" ]; then
  sed -n '2,16p' "$0"
  exit 2
fi
shift
suite="../shared/reference"
repeat=20
runs=3
while [ $# -gt 0 ]; do
  case "$1" in
    --suite) suite="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    *) echo "compare.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
if [ ! -d "$suite" ]; then
  echo "compare.sh: no suite directory $suite (the shared reference files); give --suite DIR" >&2
  exit 2
fi
sha=$(git rev-parse --short=12 "$old^{commit}")

# The old commit's CLI, from git's own copy of that tree.
src="build/compare/src-$sha"
bin_old="build/compare/$sha/bin/cmkit"
if [ ! -x "$bin_old" ]; then
  echo "== building $sha's cmkit in build/compare/$sha"
  rm -rf "$src" && mkdir -p "$src"
  git archive "$sha" | tar -x -C "$src"
  cmake -S "$src" -B "build/compare/$sha" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DCMKIT_BUILD_TESTS=OFF -DCMKIT_BUILD_BENCH=OFF -DCMKIT_BUILD_FUZZ=OFF >/dev/null
  cmake --build "build/compare/$sha" --target cmkit_cli
fi

echo "== building this tree's cmkit (build/release)"
cmake --preset release >/dev/null
cmake --build --preset release --target cmkit_cli
bin_new="build/release/bin/cmkit"

out="build/compare/runs-$sha"
rm -rf "$out" && mkdir -p "$out"
for r in $(seq 1 "$runs"); do
  echo "== run $r of $runs: $sha, then this tree ($repeat passes over each file of $suite)"
  "$bin_old" bench --suite "$suite" --repeat "$repeat" >"$out/old.$r.txt"
  "$bin_new" bench --suite "$suite" --repeat "$repeat" >"$out/new.$r.txt"
done
python3 bench/compare_tables.py --old-name "$sha" --new-name "$(git rev-parse --short=12 HEAD)$(git diff --quiet HEAD || echo '+changes')" \
  --old "$out"/old.*.txt --new "$out"/new.*.txt
