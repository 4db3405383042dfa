#!/usr/bin/env python3
"""edge_gaps.py [SHARED] [--answers DIR] [--worst N]: how far each translation's edge contact
lies from the trace model where the move stopped.

For every translation of the shared reference query files (SHARED/reference*/NAME.queries.txt,
SHARED default ../shared beside the repository) whose answer is an edge contact and whose start
and end differ (a position test's "point" is no contact), the distance from the contact point to
the trace model's bounding box at the end position, in the trace model's frame (its end axis):
a lower bound of the distance to the trace model itself. A contact the move really reached lies
within the stop distance of the surfaces: 0.25 units along the edge's normal, up to 0.83 for the
folded edges of two-sided faces (docs/fidelity.md). Farther means the move stopped short of the
edge it names.

The answers are the original's (SHARED/reference*/NAME.results.txt) unless --answers DIR names
the output folder of tests/fidelity/agree_shared.sh (DIR/reference-NAME.res: cmkit's). Prints
the count per distance class and the --worst N (default 8) farthest, with file, fraction and
query. Trace models given by bounds (box, octahedron, dodecahedron, cylinder, cone) and polygons
are measured; others (bone, ...) are left out.

    python3 tests/fidelity/edge_gaps.py
    python3 tests/fidelity/edge_gaps.py --answers /tmp/agree
"""
import argparse
import collections
import glob
import math
import os
import sys

from check_lt4 import fields, numbers  # (the answer lines' parsers, beside this script)

CLASSES = [(0.3, "<= 0.3"), (1.0, "0.3-1"), (2.0, "1-2"), (5.0, "2-5"), (math.inf, "> 5")]


def trm_bounds(spec):
    """(min, max) of the trace model `spec` in its own frame, or None."""
    kind, _, rest = spec.partition(":")
    if kind in ("box", "octahedron", "dodecahedron"):
        v = numbers(rest)
        return v[:3], v[3:]
    if kind in ("cylinder", "cone"):
        v = numbers(rest.partition(":")[2])
        return v[:3], v[3:]
    if kind == "polygon":
        points = [numbers(p) for p in rest.split(";")]
        return [min(p[i] for p in points) for i in range(3)], [max(p[i] for p in points) for i in range(3)]
    return None


def gap(point, end, axis, bounds):
    """Distance from `point` to `bounds` placed at `end` with rows `axis`."""
    d = [point[i] - end[i] for i in range(3)]
    local = [sum(axis[3 * r + c] * d[c] for c in range(3)) for r in range(3)]
    lo, hi = bounds
    return math.sqrt(sum(max(lo[i] - local[i], 0.0, local[i] - hi[i]) ** 2 for i in range(3)))


def answer_file(queries, answers_dir):
    name = os.path.basename(queries)[: -len(".queries.txt")]
    if answers_dir is None:
        return queries[: -len(".queries.txt")] + ".results.txt"
    tag = os.path.basename(os.path.dirname(queries))
    return os.path.join(answers_dir, f"{tag}-{name}.res")


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter, epilog=__doc__)
    p.add_argument("shared", nargs="?", default=os.path.join(here, "..", "..", "..", "shared"))
    p.add_argument("--answers", help="agree_shared.sh's output folder (cmkit's answers)")
    p.add_argument("--worst", type=int, default=8)
    a = p.parse_args()
    files = sorted(glob.glob(os.path.join(a.shared, "reference*", "*.queries.txt")))
    if not files:
        sys.exit(f"edge_gaps.py: no reference query files under {a.shared}")
    counts = collections.Counter()
    worst = []
    for queries in files:
        answers = answer_file(queries, a.answers)
        if not os.path.exists(answers):
            print(f"(no answers for {queries}: {answers})", file=sys.stderr)
            continue
        qs = [l for l in open(queries, encoding="utf-8") if l.strip() and not l.startswith("#")]
        rs = [l for l in open(answers, encoding="utf-8") if l.strip() and not l.startswith("#")]
        if len(qs) != len(rs):
            print(f"(skipped {answers}: {len(rs)} answers to {len(qs)} queries)", file=sys.stderr)
            continue
        for q, r in zip(qs, rs):
            if not q.startswith("translation "):
                continue
            query, answer = fields(q), fields(r)
            if answer.get("type") != "edge" or query["start"] == query["end"]:
                continue
            bounds = trm_bounds(query["trm"])
            if bounds is None:
                continue
            g = gap(numbers(answer["point"]), numbers(answer["endpos"]),
                    numbers(answer.get("endaxis", "1,0,0,0,1,0,0,0,1")), bounds)
            counts[next(label for limit, label in CLASSES if g <= limit)] += 1
            worst.append((g, os.path.basename(queries), answer["fraction"], q.strip()))
    total = sum(counts.values())
    who = "cmkit's answers in " + a.answers if a.answers else "the original's answers"
    print(f"{total} translations ending at an edge contact ({who}); the contact point's distance "
          "from the trace model's bounds at the end:")
    for _, label in CLASSES:
        print(f"  {label:>7} units: {counts[label]}")
    for g, name, fraction, q in sorted(worst, reverse=True)[: a.worst]:
        print(f"  {g:7.2f}  {name}  fraction={fraction}  {q[:150]}")


if __name__ == "__main__":
    main()
