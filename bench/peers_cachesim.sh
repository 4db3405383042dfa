#!/usr/bin/env bash
# bench/peers_cachesim.sh PEERS_BINARY KIND [SCENE] [QUERIES] [embree]
#
# Memory traffic of cmkit's queries in cmkit_peers, counted, not timed: runs
# one kind's queries once under callgrind with a model of this machine's
# caches (32 KB first level, a 1 MB last level standing for one core's L2)
# and prints per query the instructions, first-level read misses and
# last-level read misses of cmkit's side only. Deterministic: two builds'
# counts compare where this machine's timing moves by more than the
# difference (docs/performance.md, "Measuring memory: callgrind's cache
# model"). KIND is a kind of cmkit_peers ('point ray', box, box+axis,
# cylinder:8, cylinder:8+axis); SCENE lt4 or generated (default generated);
# QUERIES default 20000. With `embree` as the fifth argument (rays only),
# Embree's rtcIntersect1 is counted instead of cmkit's cast. Needs valgrind.
#
#   bench/peers_cachesim.sh build/release/bin/cmkit_peers box
#   bench/peers_cachesim.sh build/release/bin/cmkit_peers 'point ray' generated 100000
#   bench/peers_cachesim.sh build/release/bin/cmkit_peers 'point ray' generated 100000 embree
#
# Each count includes the first query's one-time growth of the scratch
# memory; over 20 000 queries that is under 1 % of the instructions.
set -euo pipefail
if [ $# -lt 2 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,21p' "$0"
  exit 2
fi
peers=$(realpath "$1")
kind=$2
scene=${3:-generated}
queries=${4:-20000}
engine=${5:-cmkit}
command -v valgrind >/dev/null || { echo "peers_cachesim.sh: needs valgrind (apt-get install valgrind)" >&2; exit 2; }
peer=Bullet
if [ "$engine" = embree ]; then
  [ "$kind" = "point ray" ] || { echo "peers_cachesim.sh: embree counts rays only" >&2; exit 2; }
  toggle='rtcIntersect1*'
  peer=Embree
elif [ "$kind" = "point ray" ]; then
  toggle='cmkit::RayIndex::cast*'
else
  toggle='peers::CmkitEngine::sweep*'
fi
out=$(mktemp)
trap 'rm -f "$out"' EXIT
# (Bullet as the only peer unless Embree is counted: the run needs one, and Jolt's AVX2 code
# stops valgrind.)
valgrind --tool=callgrind --cache-sim=yes --I1=32768,8,64 --D1=32768,8,64 --LL=1048576,16,64 \
  --callgrind-out-file="$out" --toggle-collect="$toggle" \
  "$peers" --scene "$scene" --kinds "$kind" --queries "$queries" --passes 1 --build-passes 1 \
  --no-reference --peers "$peer" >/dev/null 2>&1
callgrind_annotate "$out" 2>/dev/null | awk -v q="$queries" -v kind="$kind" -v scene="$scene" -v engine="$engine" '
  /^Events shown:/ { for (i = 3; i <= NF; ++i) col[$i] = i - 2 }
  /PROGRAM TOTALS/ {
    n = 0
    for (i = 1; i <= NF; ++i) if ($i ~ /^[0-9,]+$/) { v = $i; gsub(",", "", v); val[++n] = v }
    printf "%s%s, %s scene, %d queries: %.0f instructions, %.2f first-level read misses, %.2f last-level read misses a query\n",
      engine == "embree" ? "(Embree) " : "", kind, scene, q, val[col["Ir"]] / q, val[col["D1mr"]] / q, val[col["DLmr"]] / q
  }'
