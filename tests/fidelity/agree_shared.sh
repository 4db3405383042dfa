#!/usr/bin/env bash
# agree_shared.sh CLI OUTDIR [SHARED]: cmkit's answers to every reference query file of the
# shared data folder (SHARED, default ../shared: reference/ and reference-proc/), with the
# original's edges and with --robust-edges, and agree.py's summary of each against the
# original's answers. Writes OUTDIR/TAG.res and OUTDIR/TAG.robust.res (TAG = folder-name), the
# summaries to OUTDIR/agree.txt, and prints the rotation, translation, ... lines summed per kind;
# the maps' .cm files (cmkit compile) go to OUTDIR/TAG.cm.
#
#   tests/fidelity/agree_shared.sh build/release/bin/cmkit /tmp/agree
#   diff -rq -x '*.err' /tmp/agree-before /tmp/agree   answers and .cm files that changed between two builds
set -euo pipefail
cli=$(realpath "$1")
out=$2
shared=$(realpath "${3:-$(dirname "$0")/../../../shared}")
[ -d "$shared/reference" ] || { echo "no shared data folder at $shared" >&2; exit 2; }
mkdir -p "$out"
: > "$out/agree.txt"
for dir in "$shared/reference" "$shared/reference-proc"; do
  for queries in "$dir"/*.queries.txt; do
    name=$(basename "$queries" .queries.txt)
    # The source the reference answers were made from: the .cm of rbdoom-unittests, else the .map.
    if [ -f "$shared/maps/rbdoom-unittests/$name.cm" ]; then
      src="$shared/maps/rbdoom-unittests/$name.cm"
    else
      src=$(ls "$shared"/maps/*/"$name.map" 2>/dev/null | head -1)
    fi
    [ -n "$src" ] || { echo "no map for $name" >&2; continue; }
    tag=$(basename "$dir")-$name
    "$cli" query "$src" "$queries" -o "$out/$tag.res" --threads 2 >/dev/null 2>"$out/$tag.err" || true
    "$cli" query "$src" "$queries" -o "$out/$tag.robust.res" --robust-edges --threads 2 >/dev/null \
      2>>"$out/$tag.err" || true
    case "$src" in *.map) "$cli" compile "$src" -o "$out/$tag.cm" >/dev/null 2>>"$out/$tag.err" || true ;; esac
    python3 "$shared/tools/agree.py" "$queries" "$dir/$name.results.txt" "$out/$tag.res" |
      grep -E "^(translation|rotation|contents|pointcontents|contacts) " | sed "s|^|$tag |" >>"$out/agree.txt"
  done
done
# Per kind: lines, agree, tie? and "normal flipped" summed over the files (agree.py prints
# "KIND  N lines  agree  P%  tie?  T  differ: ..., normal flipped F").
awk '{ kind=$2; lines[kind]+=$3; agree[kind]+=$3*$6/100; tie[kind]+=$8
       if (match($0, /normal flipped [0-9]+/)) flipped[kind]+=substr($0, RSTART+15, RLENGTH-15) }
     END { for (k in lines) printf "%-14s %6d lines  agree %6.0f  tie? %4d  normal flipped %4d\n",
                                   k, lines[k], agree[k], tie[k], flipped[k] }' "$out/agree.txt" | sort
