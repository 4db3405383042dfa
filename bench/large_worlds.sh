#!/usr/bin/env bash
# bench/large_worlds.sh [MAP] [--sweeps N] [--walker-steps N] [--offsets "X,Y,Z ..."]
#                       [--suite DIR] [--repeat N] [--runs R]
#
# What distance from the origin does to sweeps, in the float build (preset
# release) and the double build (preset double, -DCMKIT_DOUBLE=ON), and what
# double costs in speed, measured in one run on this machine:
#  1. builds both presets' CLI;
#  2. runs `cmkit soak MAP --offset X,Y,Z` (the map's world moved before it is
#     built) with each build at each offset and prints the soak's counts per
#     class (docs/reliability.md explains them) as one table;
#  3. when DIR exists, runs `cmkit bench --suite DIR --repeat N` with both
#     builds, alternating, R times, and prints the double build's speed
#     against the float build's (bench/compare_tables.py: below 1, double is
#     slower);
#  4. when DIR has the original's answers (NAME.queries.txt, NAME.results.txt)
#     and ../shared/maps the maps, runs `cmkit query` of each with both builds
#     and prints the agreement per kind (../shared/tools/agree.py, summed).
#
#   bench/large_worlds.sh                 # lt4, 1M sweeps, 100k walker steps, offsets 0 to 100000
#   bench/large_worlds.sh data/maps/lt4/lt4.map --sweeps 100000 --walker-steps 10000 --runs 1
set -euo pipefail
cd "$(dirname "$0")/.."

map="data/maps/lt4/lt4.map"
sweeps=1000000
walker=100000
offsets="0,0,0 10000,10000,0 40000,40000,0 100000,100000,0"
suite="../shared/reference"
repeat=5
runs=3
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then map="$1"; shift; fi
while [ $# -gt 0 ]; do
  case "$1" in
    --sweeps) sweeps="$2"; shift 2 ;;
    --walker-steps) walker="$2"; shift 2 ;;
    --offsets) offsets="$2"; shift 2 ;;
    --suite) suite="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --runs) runs="$2"; shift 2 ;;
    -h | --help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "large_worlds.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done

for preset in release double; do
  echo "== building the $preset preset's cmkit (build/$preset)"
  cmake --preset "$preset" >/dev/null
  cmake --build --preset "$preset" --target cmkit_cli
done

out="build/large-worlds"
rm -rf "$out" && mkdir -p "$out"
for preset in release double; do
  for offset in $offsets; do
    echo "== $preset: soak $map moved by $offset"
    "build/$preset/bin/cmkit" soak "$map" --offset "$offset" --sweeps "$sweeps" --walker-steps "$walker" \
      --threads 2 --examples 0 >"$out/soak-$preset-$offset.txt"
  done
done
python3 - "$out" "$offsets" <<'PY'
import re, sys
out, offsets = sys.argv[1], sys.argv[2].split()
classes = ["brush-face", "patch-behind", "grazing", "precision", "closed-brush", "other-polygon",
           "walker-embedded", "walker-stuck", "non-finite", "fraction-range"]
print("| build | offset | " + " | ".join(classes) + " | ends in solid |")
print("|---" * (len(classes) + 3) + "|")
for preset, name in (("release", "float"), ("double", "double")):
    for offset in offsets:
        text = open(f"{out}/soak-{preset}-{offset}.txt", encoding="utf-8").read()
        counts = {c: int(re.search(rf"^\s+{c}\s+(\d+)", text, re.M).group(1)) for c in classes}
        solid = sum(counts[c] for c in classes[:6])
        print(f"| {name} | {offset} | " + " | ".join(str(counts[c]) for c in classes) + f" | {solid} |")
PY

if [ -d "$suite" ]; then
  for r in $(seq 1 "$runs"); do
    echo "== speed run $r of $runs: float, then double ($repeat passes over each file of $suite)"
    build/release/bin/cmkit bench --suite "$suite" --repeat "$repeat" >"$out/float.$r.txt" 2>/dev/null
    build/double/bin/cmkit bench --suite "$suite" --repeat "$repeat" >"$out/double.$r.txt" 2>/dev/null
  done
  python3 bench/compare_tables.py --old-name float --new-name double \
    --old "$out"/float.*.txt --new "$out"/double.*.txt
else
  echo "(no $suite: speed comparison left out; give --suite DIR)"
fi

agree="../shared/tools/agree.py"
if [ -d "$suite" ] && [ -f "$agree" ]; then
  echo "== agreement with the original's answers ($agree over $suite), float and double"
  for q in "$suite"/*.queries.txt; do
    name=$(basename "$q" .queries.txt)
    m=$(find ../shared/maps -name "$name.map" | head -1)
    [ -n "$m" ] || continue
    for preset in release double; do
      "build/$preset/bin/cmkit" query "$m" "$q" >"$out/$preset-$name.out" 2>/dev/null || true
      python3 "$agree" "$q" "$suite/$name.results.txt" "$out/$preset-$name.out" --json >"$out/$preset-$name.json"
    done
  done
  python3 - "$out" <<'PY'
import collections, glob, json, sys
out = sys.argv[1]
for preset, name in (("release", "float"), ("double", "double")):
    total = collections.defaultdict(lambda: [0, 0])
    for path in glob.glob(f"{out}/{preset}-*.json"):
        for kind, v in json.load(open(path, encoding="utf-8")).items():
            if isinstance(v, dict) and "lines" in v:
                total[kind][0] += v["lines"] - v.get("refused", 0)
                total[kind][1] += v["agree"] + v.get("tie?", 0)
    print(f"{name:7}" + "".join(f"  {k} {100 * a / n:.2f}% of {n}" for k, (n, a) in sorted(total.items())))
PY
fi
