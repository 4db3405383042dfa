#!/usr/bin/env bash
# bench/peers_pairs.sh OLD_PEERS NEW_PEERS PAIRS KINDS [SCENE] [QUERIES] [PASSES]
#
# Two builds' cmkit_peers timed in turn on the same queries, PAIRS times
# (OLD, NEW, OLD, NEW, ...), each run with Jolt beside cmkit in the same
# process. Prints every run's cmkit ns and cmkit/Jolt ratio, then per kind
# the new/old time of each pair (the two runs next to each other, so a
# burst of load on the machine falls on both) and its median, and each
# build's cmkit/Jolt ratios: range, median, how many runs above 1, each run's. On the shared VM one run moves by
# up to 20 %: a step is judged by the median over six or more pairs
# (DEVELOPERS.md, bench/). KINDS as cmkit_peers --kinds (e.g.
# 'box,box+axis'); SCENE lt4 or generated (default generated); QUERIES
# default 10000; PASSES default 5 (the fastest pass counts).
#
#   bench/peers_pairs.sh /tmp/peers-old build/release/bin/cmkit_peers 8 'box,box+axis'
#   bench/peers_pairs.sh /tmp/peers-old build/release/bin/cmkit_peers 6 'point ray' generated 100000
set -euo pipefail
if [ $# -lt 4 ] || [ "$1" = "-h" ] || [ "$1" = "--help" ]; then
  sed -n '2,17p' "$0"
  exit 2
fi
old=$1
new=$2
pairs=$3
kinds=$4
scene=${5:-generated}
queries=${6:-10000}
passes=${7:-5}
peer=Jolt
[ "$kinds" = "point ray" ] && peer=Embree
for bin in "$old" "$new"; do
  [ -x "$bin" ] || { echo "peers_pairs.sh: $bin is not an executable" >&2; exit 2; }
done
runs=$(mktemp)
trap 'rm -f "$runs"' EXIT
for ((i = 1; i <= pairs; i++)); do
  for which in old new; do
    bin=$old
    [ "$which" = new ] && bin=$new
    # A kind's timing line: the kind, cmkit ns, then the peers' ns and ratios; the
    # ratio against the one peer asked for is the last number on the line.
    "$bin" --scene "$scene" --kinds "$kinds" --queries "$queries" --passes "$passes" --build-passes 1 \
        --no-reference --peers "$peer" 2>&1 |
      awk -v w="$which" -v p="$i" '
        /^(point ray|box|cylinder)/ {
          kind = $1; if ($1 == "point") kind = "point ray"
          n = split($0, f, /  +/)
          if (f[2] ~ /^[0-9.]+$/ && f[2] > 0) {
            ratio = "-"; for (k = n; k > 2; k--) if (f[k] ~ /^[0-9.]+$/) { ratio = f[k]; break }
            print p "\t" w "\t" kind "\t" f[2] "\t" ratio
          }
        }' >> "$runs"
  done
done
python3 - "$runs" <<'EOF'
import statistics, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
kinds = []
for r in rows:
    if r[2] not in kinds:
        kinds.append(r[2])
for kind in kinds:
    t = {}
    ratio = {"old": [], "new": []}
    for p, which, k, ns, r in rows:
        if k != kind:
            continue
        t[(p, which)] = float(ns)
        if r != "-":
            ratio[which].append(float(r))
    pairs = sorted({p for p, _ in t}, key=int)
    per = [t[(p, "new")] / t[(p, "old")] for p in pairs if (p, "old") in t and (p, "new") in t]
    print(f"{kind}: ns old {' '.join(str(int(t[(p, 'old')])) for p in pairs if (p, 'old') in t)}")
    print(f"{kind}: ns new {' '.join(str(int(t[(p, 'new')])) for p in pairs if (p, 'new') in t)}")
    if per:
        print(f"{kind}: new/old per pair {' '.join(f'{x:.2f}' for x in per)}; median {statistics.median(per):.3f}")
    for which in ("old", "new"):
        if ratio[which]:
            rs = ratio[which]
            above = sum(1 for x in rs if x > 1)
            print(f"{kind}: {which} / peer {min(rs):.2f}-{max(rs):.2f}, median {statistics.median(rs):.2f}, "
                  f"above 1 in {above} of {len(rs)} ({' '.join(f'{x:.2f}' for x in rs)})")
EOF
